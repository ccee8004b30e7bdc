// One message of the JSON feed (docs/northbound.md, "MQTT"), as the publisher makes it and the
// client sends it.
#pragma once

#include <functional>
#include <vector>

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

// The monitoring's events (docs/monitoring.md, "Events") as the feed takes them: each one's
// number, its JSON and its time. The feed publishes those after the last it sent on
// <prefix>/events, QoS 1, kept in the backlog while the broker is away.
struct MqttEvent {
  std::uint64_t seq = 0;
  std::string payload;
  std::int64_t unix_ms = 0;
};
// A batch of a burst's samples (monitoring/burst_feed.h), published on
// <prefix>/<sensor>/burst, QoS 1, kept in the backlog while the broker is away.
struct MqttBurst {
  std::uint64_t seq = 0;
  std::string sensor;
  std::string payload;
  std::int64_t unix_ms = 0;  // its newest sample's
};
struct MqttEventSource {
  std::function<std::uint64_t()> last;  // the newest event's number now (0: none yet)
  std::function<std::vector<MqttEvent>(std::uint64_t after)> after;  // oldest first
  // The same for the bursts' batches.
  std::function<std::uint64_t()> last_burst;
  std::function<std::vector<MqttBurst>(std::uint64_t after)> bursts_after;
};

}  // namespace tiltgate
