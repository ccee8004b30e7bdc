#include "sparkplug/sparkplug_service.h"

#include <spdlog/spdlog.h>

#include "driver/visible_text.h"

namespace tiltgate {

namespace {

std::vector<std::string> sensor_names(const Config& config) {
  std::vector<std::string> names;
  for (const SensorConfig& sensor : config.sensors) names.push_back(sensor.name);
  return names;
}

}  // namespace

SparkplugService::SparkplugService(boost::asio::any_io_executor executor, const Gateway& gateway,
                                   FamilyList families, const SparkplugConfig& config,
                                   ClockReader clock, monitoring::BurstSource bursts)
    : executor_(std::move(executor)),
      gateway_(gateway),
      families_(families),
      config_(config),
      clock_(std::move(clock)),
      bursts_(std::move(bursts)),
      retired_(executor_),
      retry_(executor_) {
  make_node();
}

SparkplugService::~SparkplugService() = default;

void SparkplugService::make_node() {
  devices_ = sensor_names(gateway_.config());
  if (!config_.enabled || paused_) return;
  node_ = std::make_unique<sparkplug::EdgeNode>(executor_, gateway_, families_, config_, clock_,
                                                bursts_);
}

void SparkplugService::retire_node() {
  retry_.cancel();
  started_ = false;
  if (!node_) return;
  node_->stop();
  if (const auto bd_seq = node_->last_bd_seq()) last_bd_seq_ = bd_seq;
  retired_.add(std::move(node_));
}

void SparkplugService::start_as_user() {
  retry_.cancel();
  started_ = false;
  if (!node_) return;
  if (auto started = node_->start(last_bd_seq_); !started) {
    spdlog::error("Sparkplug edge node off: {}; tried again every {} s", started.error(),
                  StartRetry::kInterval.count());
    retry_.schedule([this] { return start_again(); });
    return;
  }
  log_started();
}

bool SparkplugService::start_again() {
  // A node whose start failed is not used again: a new one, as at a reload.
  retire_node();
  make_node();
  if (!node_) return true;
  if (auto started = node_->start(last_bd_seq_); !started) {
    spdlog::debug("Sparkplug edge node still off: {}", started.error());
    return false;
  }
  log_started();
  return true;
}

void SparkplugService::log_started() {
  started_ = true;
  spdlog::info("Sparkplug edge node {}/{} to {}:{}, state in {}", visible_text(config_.group_id),
               visible_text(config_.edge_node_id), visible_text(config_.host), config_.port,
               visible_text(config_.state_dir));
}

bool SparkplugService::reload(const Config& loaded, const ConfigDiff& diff) {
  // The devices and their aliases are fixed for a session: other sensors, another session.
  // A node that could not start (its state_dir not writable) is tried again: fixing the folder
  // needs no restart.
  const bool off = node_ && !started_;
  // Off before and after, or paused (resume() makes the node anew): the sensors may change,
  // but there is no edge node to restart.
  if (paused_ || (!node_ && !loaded.sparkplug.enabled)) {
    config_ = loaded.sparkplug;
    devices_ = sensor_names(loaded);
    return false;
  }
  if (!off && !diff.sparkplug_changed && sensor_names(loaded) == devices_) return false;
  retire_node();
  config_ = loaded.sparkplug;
  make_node();
  start_as_user();
  return true;
}

void SparkplugService::pause() {
  paused_ = true;
  retire_node();
}

void SparkplugService::resume() {
  if (!paused_) return;
  paused_ = false;
  make_node();
  start_as_user();
}

void SparkplugService::stop() {
  retry_.cancel();
  if (node_) node_->stop();
}

std::optional<SparkplugStats> SparkplugService::stats() const {
  if (!node_ || !started_) return std::nullopt;
  return node_->stats();
}

std::optional<StoreStats> SparkplugService::store_stats() const {
  if (!node_ || !started_) return std::nullopt;
  return node_->store_stats();
}

}  // namespace tiltgate
