// The MQTT feed's decisions, without a broker (docs/northbound.md, "MQTT"): when a sensor's state is due,
// which identity has changed, and the bounded backlog that holds messages while the broker is
// away. Pure: time is passed in; mqtt/mqtt_client.h sends what this produces.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>

#include "gateway/gateway_status.h"

namespace tiltgate {

struct MqttMessage {
  std::string topic;
  std::string payload;
  bool retain = false;
};

// Messages waiting for the broker, oldest first, at most `capacity`. When full, the oldest is
// dropped and counted: a subscriber that comes back wants the latest states, and an old state
// is superseded by a newer one of the same sensor anyway.
class MqttBacklog {
 public:
  explicit MqttBacklog(std::size_t capacity) : capacity_(capacity) {}

  void push(MqttMessage message);
  const MqttMessage& front() const { return messages_.front(); }
  void pop() { messages_.pop_front(); }
  bool empty() const { return messages_.empty(); }
  std::size_t size() const { return messages_.size(); }
  std::uint64_t dropped() const { return dropped_; }

 private:
  std::size_t capacity_;
  std::deque<MqttMessage> messages_;
  std::uint64_t dropped_ = 0;
};

struct MqttPacing {
  std::chrono::milliseconds interval{1000};  // a sensor's state at least this often
  // Sooner when x or y moved this much since the last publish; 0: at every new reading.
  double on_change_deg = 0.01;
  std::chrono::milliseconds min_spacing{100};  // the soonest a state follows the previous one
};

// What the decision looks at in one sensor's state.
struct StateSample {
  std::optional<double> x;
  std::optional<double> y;
  bool online = false;
  std::uint64_t readings = 0;  // polls that brought a reading so far: a new one changes it
};

// One sensor's pacing: due at the first sample, when `interval` has passed since the last
// publish, when `online` flips, and (after min_spacing) when an angle moved by on_change_deg
// since the last publish, or for 0 when a new reading arrived.
class StatePacer {
 public:
  using Clock = std::chrono::steady_clock;

  explicit StatePacer(MqttPacing pacing) : pacing_(pacing) {}
  bool due(const StateSample& sample, Clock::time_point now) const;
  void published(const StateSample& sample, Clock::time_point now);

 private:
  bool moved(const StateSample& sample) const;

  MqttPacing pacing_;
  std::optional<StateSample> last_;
  Clock::time_point last_at_{};
};

struct MqttPublisherOptions {
  std::string topic_prefix;
  MqttPacing pacing;
  std::size_t backlog = 1000;
};

// Turns status copies into messages in the backlog: each sensor's state when its pacer says
// so, and its info (retained) when it differs from the last one queued.
class MqttPublisher {
 public:
  using Clock = std::chrono::steady_clock;

  explicit MqttPublisher(MqttPublisherOptions options);

  void take(const GatewayStatus& status, Clock::time_point now, std::int64_t now_unix_ms);
  // After a (re)connect: the broker may have restarted without its retained messages, so every
  // sensor's info is queued again at the next take().
  void forget_info() { info_.clear(); }

  MqttBacklog& backlog() { return backlog_; }
  const MqttBacklog& backlog() const { return backlog_; }

 private:
  MqttPublisherOptions options_;
  std::map<std::string, StatePacer> pacers_;  // by sensor name
  std::map<std::string, std::string> info_;   // the last info payload queued, by sensor name
  MqttBacklog backlog_;
};

}  // namespace tiltgate
