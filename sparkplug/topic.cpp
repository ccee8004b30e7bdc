#include "sparkplug/topic.h"

#include <array>
#include <cstdint>
#include <vector>

namespace tiltgate::sparkplug {
namespace {

constexpr std::array<MessageType, 9> kTypes = {
    MessageType::NBIRTH, MessageType::NDATA,  MessageType::NDEATH,
    MessageType::NCMD,   MessageType::DBIRTH, MessageType::DDATA,
    MessageType::DDEATH, MessageType::DCMD,   MessageType::STATE};

std::vector<std::string_view> split(std::string_view text) {
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t slash = text.find('/', start);
    parts.push_back(text.substr(start, slash - start));
    if (slash == std::string_view::npos) return parts;
    start = slash + 1;
  }
}

}  // namespace

std::string_view message_type_name(MessageType type) {
  switch (type) {
    case MessageType::NBIRTH: return "NBIRTH";
    case MessageType::NDATA: return "NDATA";
    case MessageType::NDEATH: return "NDEATH";
    case MessageType::NCMD: return "NCMD";
    case MessageType::DBIRTH: return "DBIRTH";
    case MessageType::DDATA: return "DDATA";
    case MessageType::DDEATH: return "DDEATH";
    case MessageType::DCMD: return "DCMD";
    case MessageType::STATE: return "STATE";
  }
  return "?";
}

bool is_device_message(MessageType type) {
  return type == MessageType::DBIRTH || type == MessageType::DDATA || type == MessageType::DDEATH ||
         type == MessageType::DCMD;
}

std::string node_topic(MessageType type, std::string_view group_id, std::string_view edge_node_id) {
  std::string topic(kNamespace);
  topic.append("/").append(group_id).append("/").append(message_type_name(type));
  topic.append("/").append(edge_node_id);
  return topic;
}

std::string device_topic(MessageType type, std::string_view group_id, std::string_view edge_node_id,
                         std::string_view device_id) {
  return node_topic(type, group_id, edge_node_id).append("/").append(device_id);
}

std::string state_topic(std::string_view host_id) {
  return std::string(kNamespace).append("/STATE/").append(host_id);
}

std::string to_string(const Topic& topic) {
  if (topic.type == MessageType::STATE) return state_topic(topic.edge_node_id);
  if (is_device_message(topic.type)) {
    return device_topic(topic.type, topic.group_id, topic.edge_node_id, topic.device_id);
  }
  return node_topic(topic.type, topic.group_id, topic.edge_node_id);
}

Expected<Topic, std::string> parse_topic(std::string_view text) {
  const auto parts = split(text);
  if (parts.size() < 3 || parts[0] != kNamespace) {
    return Unexpected("\"" + std::string(text) + "\" is not a Sparkplug B topic (spBv1.0/...)");
  }
  if (parts[1] == "STATE") {
    if (parts.size() != 3) return Unexpected("a STATE topic has one host id: " + std::string(text));
    if (auto problem = check_id("the host id", parts[2])) return Unexpected(*problem);
    return Topic{MessageType::STATE, "", std::string(parts[2]), ""};
  }
  std::optional<MessageType> type;
  for (MessageType t : kTypes) {
    if (t != MessageType::STATE && message_type_name(t) == parts[2]) type = t;
  }
  if (!type) return Unexpected("unknown message type \"" + std::string(parts[2]) + "\"");
  const std::size_t expected = is_device_message(*type) ? 5 : 4;
  if (parts.size() != expected) {
    return Unexpected("a " + std::string(parts[2]) + " topic has " + std::to_string(expected) +
                      " levels: " + std::string(text));
  }
  Topic topic{*type, std::string(parts[1]), std::string(parts[3]),
              expected == 5 ? std::string(parts[4]) : std::string()};
  if (auto problem = check_id("the group_id", topic.group_id)) return Unexpected(*problem);
  if (auto problem = check_id("the edge_node_id", topic.edge_node_id)) return Unexpected(*problem);
  if (expected == 5) {
    if (auto problem = check_id("the device_id", topic.device_id)) return Unexpected(*problem);
  }
  return topic;
}

}  // namespace tiltgate::sparkplug
