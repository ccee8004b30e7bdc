// The Sparkplug topic namespace (Sparkplug 3.0.0, 4.1 "Topic Namespace Elements"):
//   spBv1.0/<group_id>/{NBIRTH,NDATA,NDEATH,NCMD}/<edge_node_id>
//   spBv1.0/<group_id>/{DBIRTH,DDATA,DDEATH,DCMD}/<edge_node_id>/<device_id>
//   spBv1.0/STATE/<sparkplug_host_id>
// Building and parsing them, and checking the ids that go into them. Pure.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "config/sparkplug_id.h"
#include "driver/expected.h"

namespace tiltgate::sparkplug {

inline constexpr std::string_view kNamespace = "spBv1.0";

enum class MessageType { NBIRTH, NDATA, NDEATH, NCMD, DBIRTH, DDATA, DDEATH, DCMD, STATE };

std::string_view message_type_name(MessageType type);
// DBIRTH, DDATA, DDEATH and DCMD name a device; the others do not.
bool is_device_message(MessageType type);

struct Topic {
  MessageType type = MessageType::NDATA;
  std::string group_id;      // empty for STATE
  std::string edge_node_id;  // for STATE: the host id
  std::string device_id;     // only for the device message types

  bool operator==(const Topic&) const = default;
};

// The topic's text; the ids are put in as they are (check them with check_id first).
std::string node_topic(MessageType type, std::string_view group_id, std::string_view edge_node_id);
std::string device_topic(MessageType type, std::string_view group_id, std::string_view edge_node_id,
                         std::string_view device_id);
std::string state_topic(std::string_view host_id);
std::string to_string(const Topic& topic);

// A Sparkplug B topic, or why `text` is not one (another namespace, an unknown message type,
// a device id missing or one too many, an id that check_id refuses).
Expected<Topic, std::string> parse_topic(std::string_view text);

}  // namespace tiltgate::sparkplug
