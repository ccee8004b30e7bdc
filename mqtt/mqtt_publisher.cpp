#include "mqtt/mqtt_publisher.h"

#include <cmath>

#include "mqtt/mqtt_payload.h"

namespace tiltgate {

void MqttBacklog::push(MqttMessage message) {
  if (capacity_ == 0) {
    ++dropped_;
    return;
  }
  if (messages_.size() == capacity_) {
    messages_.pop_front();
    ++dropped_;
  }
  messages_.push_back(std::move(message));
}

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
  if (since >= pacing_.interval || sample.online != last_->online) return true;
  return since >= pacing_.min_spacing && moved(sample);
}

void StatePacer::published(const StateSample& sample, Clock::time_point now) {
  last_ = sample;
  last_at_ = now;
}

MqttPublisher::MqttPublisher(MqttPublisherOptions options)
    : options_(std::move(options)), backlog_(options_.backlog) {}

void MqttPublisher::take(const GatewayStatus& status, Clock::time_point now,
                         std::int64_t now_unix_ms) {
  for (const SensorStatus& sensor : status.sensors) {
    std::string info = mqtt_info_json(sensor);
    auto known = info_.find(sensor.name);
    if (known == info_.end() || known->second != info) {
      backlog_.push({mqtt_info_topic(options_.topic_prefix, sensor.name), info, true});
      info_[sensor.name] = std::move(info);
    }
    const StateSample sample{sensor.x, sensor.y, sensor.online, sensor.polls_ok};
    StatePacer& pacer = pacers_.try_emplace(sensor.name, options_.pacing).first->second;
    if (!pacer.due(sample, now)) continue;
    backlog_.push({mqtt_state_topic(options_.topic_prefix, sensor.name),
                   mqtt_state_json(sensor, now_unix_ms), false});
    pacer.published(sample, now);
  }
}

}  // namespace tiltgate
