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

// Well-formed UTF-8 (RFC 3629): no overlong forms, no surrogates, nothing above U+10FFFF.
bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto b = static_cast<std::uint8_t>(s[i]);
    std::size_t extra = 0;
    std::uint32_t code = 0;
    if (b < 0x80) {
      ++i;
      continue;
    } else if ((b & 0xE0) == 0xC0) {
      extra = 1;
      code = b & 0x1F;
    } else if ((b & 0xF0) == 0xE0) {
      extra = 2;
      code = b & 0x0F;
    } else if ((b & 0xF8) == 0xF0) {
      extra = 3;
      code = b & 0x07;
    } else {
      return false;
    }
    if (i + extra >= s.size()) return false;  // the sequence is cut short
    for (std::size_t k = 1; k <= extra; ++k) {
      const auto c = static_cast<std::uint8_t>(s[i + k]);
      if ((c & 0xC0) != 0x80) return false;
      code = (code << 6) | (c & 0x3F);
    }
    constexpr std::array<std::uint32_t, 4> kSmallest = {0, 0x80, 0x800, 0x10000};
    if (code < kSmallest[extra] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) {
      return false;
    }
    i += extra + 1;
  }
  return true;
}

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

std::optional<std::string> check_id(std::string_view what, std::string_view id) {
  const std::string name(what);
  if (id.empty()) return name + " is empty";
  if (id.find_first_of("+#/") != std::string_view::npos) {
    return name + " \"" + std::string(id) + "\" has '+', '#' or '/', which Sparkplug reserves";
  }
  if (id.find('\0') != std::string_view::npos) return name + " has a NUL character";
  if (!valid_utf8(id)) return name + " is not valid UTF-8";
  return std::nullopt;
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
