#include "mqtt/mqtt_publisher.h"

#include <cmath>

#include "mqtt/mqtt_payload.h"

namespace tiltgate {

namespace {

// An angle appearing or disappearing counts as a change of any size.
bool moved_by(std::optional<double> before, std::optional<double> now, double degrees) {
  if (before.has_value() != now.has_value()) return true;
  if (!before) return false;
  return std::abs(*now - *before) >= degrees;
}

}  // namespace

bool StatePacer::moved(const StateSample& sample) const {
  if (pacing_.on_change_deg <= 0.0) return sample.readings != last_->readings;
  return moved_by(last_->x, sample.x, pacing_.on_change_deg) ||
         moved_by(last_->y, sample.y, pacing_.on_change_deg);
}

bool StatePacer::due(const StateSample& sample, Clock::time_point now) const {
  if (!last_) return true;
  const auto since = now - last_at_;
  if (since >= pacing_.interval || sample.online != last_->online ||
      sample.wrong_device != last_->wrong_device ||
      sample.clock_synchronised != last_->clock_synchronised)
    return true;
  return since >= pacing_.min_spacing && moved(sample);
}

void StatePacer::published(const StateSample& sample, Clock::time_point now) {
  last_ = sample;
  last_at_ = now;
}

MqttPublisher::MqttPublisher(MqttPublisherOptions options)
    : options_(std::move(options)) {}

std::vector<MqttMessage> MqttPublisher::take(const GatewayStatus& status, Clock::time_point now,
                                             std::int64_t now_unix_ms) {
  std::vector<MqttMessage> due;
  for (const SensorStatus& sensor : status.sensors) {
    std::string info = mqtt_info_json(sensor);
    auto known = info_.find(sensor.name);
    if (known == info_.end() || known->second != info) {
      due.push_back({mqtt_info_topic(options_.topic_prefix, sensor.name), info, true, now_unix_ms});
      info_[sensor.name] = std::move(info);
    }
    const StateSample sample{sensor.x, sensor.y, sensor.online, sensor.polls_ok,
                             sensor.wrong_device, status.clock.synchronised};
    StatePacer& pacer = pacers_.try_emplace(sensor.name, options_.pacing).first->second;
    if (!pacer.due(sample, now)) continue;
    due.push_back({mqtt_state_topic(options_.topic_prefix, sensor.name),
                   mqtt_state_json(sensor, status.clock, now_unix_ms), false, now_unix_ms});
    pacer.published(sample, now);
  }
  return due;
}

}  // namespace tiltgate
