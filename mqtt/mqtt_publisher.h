// The MQTT feed's decisions, without a broker (docs/northbound.md, "MQTT"): when a sensor's state
// is due and which identity has changed. Pure: time is passed in; mqtt/mqtt_feed.h sends what
// this produces, or keeps it in its backlog (mqtt/mqtt_backlog.h).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gateway/gateway_status.h"
#include "mqtt/mqtt_message.h"

namespace tiltgate {

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
  bool wrong_device = false;   // another device answers in the sensor's place
  bool clock_synchronised = false;  // the gateway's clock, which stamps the readings
};

// One sensor's pacing: due at the first sample, when `interval` has passed since the last
// publish, when `online`, `wrong_device` or `clock_synchronised` flips, and (after min_spacing)
// when an angle moved by on_change_deg
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
};

// Turns status copies into messages: each sensor's state when its pacer says so, and its info
// (retained) when it differs from the last one made.
class MqttPublisher {
 public:
  using Clock = std::chrono::steady_clock;

  explicit MqttPublisher(MqttPublisherOptions options);

  // The messages due now, in the order to send them.
  std::vector<MqttMessage> take(const GatewayStatus& status, Clock::time_point now,
                                std::int64_t now_unix_ms);
  // After a (re)connect: the broker may have restarted without its retained messages, so every
  // sensor's info is made again at the next take().
  void forget_info() { info_.clear(); }

 private:
  MqttPublisherOptions options_;
  std::map<std::string, StatePacer> pacers_;  // by sensor name
  std::map<std::string, std::string> info_;   // the last info payload made, by sensor name
};

}  // namespace tiltgate
