// One message of the JSON feed (docs/northbound.md, "MQTT"), as the publisher makes it and the
// client sends it.
#pragma once

#include <cstdint>
#include <string>

namespace tiltgate {

struct MqttMessage {
  std::string topic;
  std::string payload;
  // Retained messages (the info) are never kept for a replay: they are sent again after every
  // reconnect anyway, and an old one replayed would replace the current one on the broker.
  bool retain = false;
  std::int64_t time_unix_ms = 0;  // when it was made

  bool operator==(const MqttMessage&) const = default;
};

}  // namespace tiltgate
