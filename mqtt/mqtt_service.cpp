#include "mqtt/mqtt_service.h"

#include <spdlog/spdlog.h>

#include "driver/visible_text.h"

namespace tiltgate {

MqttService::MqttService(boost::asio::any_io_executor executor, StatusSource status,
                         const MqttConfig& config, MqttEventSource events)
    : executor_(std::move(executor)), status_(std::move(status)), events_(std::move(events)),
      config_(config),
      retired_(executor_) {
  make_feed();
}

MqttService::~MqttService() = default;

void MqttService::make_feed() {
  if (!config_.enabled || paused_) return;
  feed_ = std::make_unique<MqttFeed>(executor_, status_, config_, events_);
}

void MqttService::retire_feed() {
  if (!feed_) return;
  feed_->stop();
  retired_.add(std::move(feed_));
}

void MqttService::start_as_user() {
  if (!feed_) return;
  if (auto started = feed_->start(); !started)
    spdlog::warn("MQTT feed off: {}", visible_text(started.error()));
  else
    spdlog::info("MQTT feed to {}:{} under {}/", visible_text(config_.host), config_.port,
                 visible_text(config_.topic_prefix));
}

bool MqttService::reload(const Config& loaded, const ConfigDiff& diff) {
  if (!diff.mqtt_changed) return false;
  retire_feed();
  config_ = loaded.mqtt;
  make_feed();
  start_as_user();
  return !paused_;  // paused: nothing restarted, the new table waits for resume()
}

void MqttService::pause() {
  paused_ = true;
  retire_feed();
}

void MqttService::resume() {
  if (!paused_) return;
  paused_ = false;
  make_feed();
  start_as_user();
}

void MqttService::stop() {
  if (feed_) feed_->stop();
}

std::optional<MqttStats> MqttService::stats() const {
  if (!feed_) return std::nullopt;
  return feed_->stats();
}

}  // namespace tiltgate
