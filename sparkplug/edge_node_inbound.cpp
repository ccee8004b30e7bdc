// EdgeNodeSession (sparkplug/edge_node_session.h), what arrives on its subscriptions: node and
// device commands, and the primary host's STATE.
#include "sparkplug/edge_node_session.h"

#include <algorithm>

#include "sparkplug/host_state.h"
#include "sparkplug/topic.h"

namespace tiltgate::sparkplug {

std::vector<Action> EdgeNodeSession::on_message(std::string_view topic,
                                                std::span<const std::uint8_t> payload,
                                                Instant now) {
  std::vector<Action> out;
  const auto parsed = parse_topic(topic);
  if (!parsed) {
    ++commands_.malformed;
    return out;
  }
  const bool ours =
      parsed->group_id == options_.group_id && parsed->edge_node_id == options_.edge_node_id;
  if (parsed->type == MessageType::STATE) {
    if (options_.primary_host_id && parsed->edge_node_id == *options_.primary_host_id) {
      host_state(out, payload, now);
    }
  } else if (parsed->type == MessageType::NCMD && ours) {
    node_command(out, payload, now);
  } else if (parsed->type == MessageType::DCMD && ours) {
    device_command(out, parsed->device_id, payload);
  }
  return out;
}

void EdgeNodeSession::host_state(std::vector<Action>& out, std::span<const std::uint8_t> payload,
                                 Instant now) {
  const auto state = parse_host_state(
      std::string_view(reinterpret_cast<const char*>(payload.data()), payload.size()));
  if (!state) {
    ++commands_.malformed;
    return;
  }
  // An older STATE than the last one is stale: ignored
  // (tck-id-message-flow-edge-node-birth-publish-phid-wait-timestamp).
  if (host_timestamp_ && state->timestamp < *host_timestamp_) return;
  host_timestamp_ = state->timestamp;
  if (state->online) {
    // tck-id-operational-behavior-edge-node-birth-sequence-wait
    if (state_ == SessionState::waiting_for_host) births(out, now);
    return;
  }
  if (state_ == SessionState::live) {
    // tck-id-message-flow-edge-node-birth-publish-phid-offline: NDEATH, disconnect, start over.
    out.push_back(Publish{node_topic_for(MessageType::NDEATH), ndeath_payload(now), 1, false});
    out.push_back(Disconnect{});
    on_connection_lost();
  }
}

void EdgeNodeSession::node_command(std::vector<Action>& out, std::span<const std::uint8_t> payload,
                                   Instant now) {
  const auto command = decode(payload);
  if (!command) {
    ++commands_.malformed;
    return;
  }
  bool rebirth = false;
  for (const Metric& m : command->metrics) {
    // tck-id-operational-behavior-data-commands-ncmd-rebirth-name, -ncmd-rebirth-value
    const auto* value = std::get_if<bool>(&m.value);
    if (m.name == kRebirthMetric && value != nullptr && *value) {
      rebirth = true;
    } else {
      ++commands_.refused;
    }
  }
  if (!rebirth) return;
  if (state_ != SessionState::live) {
    ++commands_.ignored;  // the births come when the primary host is online
    return;
  }
  // tck-id-operational-behavior-data-commands-rebirth-action-1..3: no data in between, NBIRTH
  // (seq 0, the same bdSeq) and every DBIRTH, on the same connection.
  ++commands_.rebirth;
  births(out, now);
}

void EdgeNodeSession::device_command(std::vector<Action>& out, std::string_view device_id,
                                     std::span<const std::uint8_t> payload) {
  if (!options_.commands) {
    ++commands_.ignored;
    return;
  }
  const auto command = decode(payload);
  if (!command) {
    ++commands_.malformed;
    return;
  }
  Device* device = find_device(device_id);
  if (device == nullptr || !device->born) {
    commands_.refused += command->metrics.size();
    return;
  }
  const std::size_t index = index_of(*device);
  for (const Metric& m : command->metrics) {
    // By alias, as tck-id-payloads-alias-data-cmd-requirement asks; by name from a host that
    // does not use aliases.
    const auto slot =
        std::find_if(device->layout.begin(), device->layout.end(), [&](const MetricSlot& s) {
          return m.alias ? device_alias(index, s.number) == *m.alias : s.name == m.name;
        });
    const auto value = numeric_value(m.value);
    if (slot == device->layout.end() || !slot->setting || !value) {
      ++commands_.refused;
      continue;
    }
    ++commands_.write;
    out.push_back(Write{device->name, slot->name.substr(kSettingsFolder.size()), *value});
  }
}

}  // namespace tiltgate::sparkplug
