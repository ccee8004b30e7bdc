#include "sparkplug/edge_node_session.h"

#include <algorithm>
#include <set>

#include "sparkplug/host_state.h"
#include "sparkplug/topic.h"

namespace tiltgate::sparkplug {
namespace {

std::uint64_t unix_ms(Instant now) {
  return static_cast<std::uint64_t>(std::max<std::int64_t>(now.unix_ms, 0));
}

// The time a device's metrics carry: the reading's (tck-id-payloads-name-birth-data-requirement
// asks for one on every metric), or now before the first reading. Never later than the
// message's own time: a bus can publish a reading between the moment a sample is timed and
// the moment its snapshot is read, and the reading's time, carried over from the steady
// clock, can round 1 ms the other way.
std::uint64_t reading_time(const DeviceSample& sample, Instant now) {
  if (!sample.reading_unix_ms) return unix_ms(now);
  return std::min(static_cast<std::uint64_t>(std::max<std::int64_t>(*sample.reading_unix_ms, 0)),
                  unix_ms(now));
}

}  // namespace

Expected<EdgeNodeSession, std::string> EdgeNodeSession::create(
    EdgeNodeOptions options, std::vector<std::string> devices,
    std::optional<std::uint8_t> last_bd_seq) {
  if (auto problem = check_id("group_id", options.group_id)) return Unexpected(*problem);
  if (auto problem = check_id("edge_node_id", options.edge_node_id)) return Unexpected(*problem);
  if (options.primary_host_id) {
    if (auto problem = check_id("primary_host_id", *options.primary_host_id)) {
      return Unexpected(*problem);
    }
  }
  if (options.min_interval.count() < 0 || options.max_interval < options.min_interval ||
      options.max_interval.count() <= 0) {
    return Unexpected(
        std::string("the intervals must be 0 <= min_interval <= max_interval, "
                    "max_interval > 0"));
  }
  if (!(options.on_change_deg >= 0)) return Unexpected(std::string("on_change_deg is negative"));
  std::set<std::string> seen;
  std::vector<Device> list;
  for (std::string& name : devices) {
    if (auto problem = check_id("the device id", name)) return Unexpected(*problem);
    if (!seen.insert(name).second) return Unexpected("the device id \"" + name + "\" repeats");
    list.push_back(Device{std::move(name), {}, false, {}, {}});
  }
  return EdgeNodeSession(std::move(options), std::move(list), last_bd_seq);
}

EdgeNodeSession::EdgeNodeSession(EdgeNodeOptions options, std::vector<Device> devices,
                                 std::optional<std::uint8_t> last_bd_seq)
    : options_(std::move(options)), devices_(std::move(devices)), last_bd_seq_(last_bd_seq) {}

std::uint64_t EdgeNodeSession::next_seq() {
  // tck-id-payloads-sequence-num-incrementing: up by one a message, 255 is followed by 0.
  const std::uint8_t seq = seq_;
  seq_ = static_cast<std::uint8_t>(seq_ + 1);
  return seq;
}

std::string EdgeNodeSession::node_topic_for(MessageType type) const {
  return node_topic(type, options_.group_id, options_.edge_node_id);
}

std::string EdgeNodeSession::device_topic_for(MessageType type, const Device& device) const {
  return device_topic(type, options_.group_id, options_.edge_node_id, device.name);
}

EdgeNodeSession::Device* EdgeNodeSession::find_device(std::string_view name) {
  for (Device& d : devices_) {
    if (d.name == name) return &d;
  }
  return nullptr;
}

std::size_t EdgeNodeSession::index_of(const Device& device) const {
  return static_cast<std::size_t>(&device - devices_.data());
}

Payload EdgeNodeSession::ndeath_payload(Instant now) const {
  // No seq (tck-id-topics-ndeath-seq), the bdSeq metric only (tck-id-topics-ndeath-payload).
  return Payload{unix_ms(now), std::nullopt, {bd_seq_metric(bd_seq_, unix_ms(now))}};
}

Will EdgeNodeSession::begin_connect(Instant now) {
  if (state_ != SessionState::disconnected) on_connection_lost();
  // tck-id-topics-nbirth-bdseq-increment: from 0, up by one on every CONNECT, 255 then 0. An
  // attempt that sent no CONNECT (refused, timed out) did not use its bdSeq: this one does.
  bd_seq_ = last_bd_seq_ ? static_cast<std::uint8_t>(*last_bd_seq_ + 1) : 0;
  state_ = SessionState::connecting;
  return Will{node_topic_for(MessageType::NDEATH), ndeath_payload(now), 1, false, bd_seq_};
}

void EdgeNodeSession::connect_sent() { last_bd_seq_ = bd_seq_; }

std::vector<Action> EdgeNodeSession::on_connected(Instant now) {
  std::vector<Action> out;
  // Before any birth (tck-id-message-flow-edge-node-ncmd-subscribe, -device-dcmd-subscribe:
  // QoS 1); one DCMD subscription covers every device of the node.
  out.push_back(Subscribe{node_topic_for(MessageType::NCMD), 1});
  out.push_back(
      Subscribe{device_topic(MessageType::DCMD, options_.group_id, options_.edge_node_id, "+"), 1});
  host_timestamp_.reset();
  if (options_.primary_host_id) {
    out.push_back(Subscribe{state_topic(*options_.primary_host_id), 1});
    state_ = SessionState::waiting_for_host;
  } else {
    births(out, now);
  }
  return out;
}

void EdgeNodeSession::on_connection_lost() {
  state_ = SessionState::disconnected;
  for (Device& d : devices_) d.born = false;
}

std::vector<Action> EdgeNodeSession::stop(Instant now) {
  std::vector<Action> out;
  if (state_ == SessionState::live || state_ == SessionState::waiting_for_host) {
    out.push_back(Publish{node_topic_for(MessageType::NDEATH), ndeath_payload(now), 1, false});
  }
  if (state_ != SessionState::disconnected) out.push_back(Disconnect{});
  on_connection_lost();
  return out;
}

void EdgeNodeSession::births(std::vector<Action>& out, Instant now) {
  // NBIRTH with seq 0 and this connection's bdSeq (tck-id-payloads-nbirth-seq,
  // tck-id-topics-nbirth-bdseq-matching), QoS 0, not retained (tck-id-topics-nbirth-mqtt);
  // then a DBIRTH for every device online now, before any data (tck-id-payloads-dbirth-order).
  state_ = SessionState::live;
  seq_ = 0;
  out.push_back(Publish{node_topic_for(MessageType::NBIRTH),
                        Payload{unix_ms(now), next_seq(),
                                node_birth_metrics(options_.node, node_, bd_seq_, unix_ms(now))},
                        0, false});
  node_reported_ = node_;
  node_reported_at_ = now.steady;
  for (Device& d : devices_) {
    d.born = false;
    if (d.sample && d.sample->online) device_birth(out, d, now);
  }
}

void EdgeNodeSession::device_birth(std::vector<Action>& out, Device& device, Instant now) {
  const DeviceSample& sample = *device.sample;
  device.layout = device_layout(sample);
  std::vector<Value> values = device_values(device.layout, sample);
  const std::uint64_t timestamp = reading_time(sample, now);
  std::vector<Metric> metrics;
  for (std::size_t i = 0; i < device.layout.size(); ++i) {
    metrics.push_back(
        device_metric(device.layout[i], index_of(device), values[i], timestamp, true));
  }
  out.push_back(Publish{device_topic_for(MessageType::DBIRTH, device),
                        Payload{unix_ms(now), next_seq(), std::move(metrics)}, 0, false});
  device.born = true;
  device.last = LastReport{std::move(values), sample.reading_unix_ms, now.steady};
}

std::vector<Action> EdgeNodeSession::update(std::span<const DeviceSample> samples, Instant now) {
  std::vector<Action> out;
  for (const DeviceSample& sample : samples) {
    Device* device = find_device(sample.name);
    if (device == nullptr) continue;
    device->sample = sample;
    device_update(out, *device, sample, now);
  }
  return out;
}

std::vector<Action> EdgeNodeSession::update_node(const NodeSample& sample, Instant now) {
  std::vector<Action> out;
  node_ = sample;
  // Not kept for the store while offline: the next NBIRTH carries the state as it is then.
  if (state_ != SessionState::live) return out;
  const bool error_due = now.steady - node_reported_at_ >= options_.max_interval;
  std::vector<Metric> metrics = node_data_metrics(node_reported_, sample, error_due, unix_ms(now));
  if (metrics.empty()) return out;
  // The next seq, as every message but NDEATH; QoS 0, not retained (tck-id-topics-ndata-seq-num,
  // tck-id-topics-ndata-mqtt).
  out.push_back(Publish{node_topic_for(MessageType::NDATA),
                        Payload{unix_ms(now), next_seq(), std::move(metrics)}, 0, false});
  node_reported_ = sample;
  node_reported_at_ = now.steady;
  return out;
}

void EdgeNodeSession::device_update(std::vector<Action>& out, Device& device,
                                    const DeviceSample& sample, Instant now) {
  std::vector<MetricSlot> layout = device_layout(sample);
  if (state_ == SessionState::live) {
    if (!device.born) {
      if (sample.online) device_birth(out, device, now);
      return;
    }
    if (!sample.online) {
      // tck-id-operational-behavior-device-ddeath; a DDEATH has a seq
      // (tck-id-topics-ddeath-seq-num).
      out.push_back(Publish{device_topic_for(MessageType::DDEATH, device),
                            Payload{unix_ms(now), next_seq(), {}}, 0, false});
      device.born = false;
      return;
    }
    if (layout != device.layout) {  // another model or settings: the DBIRTH is out of date
      device_birth(out, device, now);
      return;
    }
  } else {
    if (!sample.online) return;
    if (layout != device.layout) {
      device.layout = std::move(layout);
      device.last.values.clear();
    }
  }
  std::vector<Value> values = device_values(device.layout, sample);
  const ExceptionRules rules = exception_rules();
  if (!ddata_due(rules, device.layout, device.last, values, sample.reading_unix_ms, now.steady))
    return;
  const bool live = state_ == SessionState::live;
  const std::uint64_t timestamp = reading_time(sample, now);
  std::vector<Metric> metrics = data_metrics(
      device, values,
      ddata_slots(rules, device.layout, device.last, values, sample.reading_unix_ms, now.steady),
      !live, timestamp);
  if (metrics.empty()) return;
  if (live) {
    out.push_back(Publish{device_topic_for(MessageType::DDATA, device),
                          Payload{unix_ms(now), next_seq(), std::move(metrics)}, 0, false});
  } else {
    out.push_back(Keep{device_topic_for(MessageType::DDATA, device),
                       Payload{unix_ms(now), std::nullopt, std::move(metrics)},
                       static_cast<std::int64_t>(timestamp)});
  }
  device.last = LastReport{std::move(values), sample.reading_unix_ms, now.steady};
}

ExceptionRules EdgeNodeSession::exception_rules() const {
  return ExceptionRules{options_.on_change_deg, options_.min_interval, options_.max_interval};
}

std::vector<Metric> EdgeNodeSession::data_metrics(const Device& device,
                                                  const std::vector<Value>& values,
                                                  const std::vector<std::size_t>& slots,
                                                  bool named, std::uint64_t timestamp) const {
  std::vector<Metric> metrics;
  for (std::size_t i : slots) {
    Metric m = device_metric(device.layout[i], index_of(device), values[i], timestamp, false);
    if (named) {  // kept for the store: by name, since the aliases belong to a birth
      m.name = device.layout[i].name;
      m.alias.reset();
      m.is_historical = true;
    }
    metrics.push_back(std::move(m));
  }
  return metrics;
}

Expected<Publish, ReplayRefusal> EdgeNodeSession::replay(std::string_view topic,
                                                         std::span<const std::uint8_t> payload,
                                                         Instant now) {
  if (state_ != SessionState::live) return Unexpected(ReplayRefusal::not_live);
  const auto parsed = parse_topic(topic);
  if (!parsed || parsed->type != MessageType::DDATA || parsed->group_id != options_.group_id ||
      parsed->edge_node_id != options_.edge_node_id) {
    return Unexpected(ReplayRefusal::malformed);
  }
  Device* device = find_device(parsed->device_id);
  if (device == nullptr) return Unexpected(ReplayRefusal::unknown_device);
  if (!device->born) return Unexpected(ReplayRefusal::device_offline);
  auto kept = decode(payload);
  if (!kept) return Unexpected(ReplayRefusal::malformed);
  std::vector<Metric> metrics;
  for (Metric& m : kept->metrics) {
    const auto slot = std::find_if(device->layout.begin(), device->layout.end(),
                                   [&](const MetricSlot& s) { return s.name == m.name; });
    if (slot == device->layout.end()) continue;  // not in this birth: the host would not know it
    m.alias = device_alias(index_of(*device), slot->number);
    m.name.clear();
    m.is_historical = true;
    metrics.push_back(std::move(m));
  }
  if (metrics.empty()) return Unexpected(ReplayRefusal::malformed);
  return Publish{device_topic_for(MessageType::DDATA, *device),
                 Payload{unix_ms(now), next_seq(), std::move(metrics)}, 0, false};
}

// What arrives on the subscriptions: node and device commands, and the primary host's STATE.
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
