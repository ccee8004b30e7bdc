#include "sparkplug/sparkplug_service.h"

#include <spdlog/spdlog.h>

namespace tiltgate {

namespace {

std::vector<std::string> sensor_names(const Config& config) {
  std::vector<std::string> names;
  for (const SensorConfig& sensor : config.sensors) names.push_back(sensor.name);
  return names;
}

}  // namespace

SparkplugService::SparkplugService(boost::asio::any_io_executor executor, const Gateway& gateway,
                                   FamilyList families, const SparkplugConfig& config)
    : executor_(std::move(executor)),
      gateway_(gateway),
      families_(families),
      config_(config),
      retired_(executor_) {
  make_node();
}

SparkplugService::~SparkplugService() = default;

void SparkplugService::make_node() {
  devices_ = sensor_names(gateway_.config());
  if (!config_.enabled) return;
  node_ = std::make_unique<sparkplug::EdgeNode>(executor_, gateway_, families_, config_);
}

void SparkplugService::start_as_user() {
  started_ = false;
  if (!node_) return;
  if (auto started = node_->start(); !started) {
    spdlog::error("Sparkplug edge node off: {}", started.error());
    return;
  }
  started_ = true;
  spdlog::info("Sparkplug edge node {}/{} to {}:{}, state in {}", config_.group_id,
               config_.edge_node_id, config_.host, config_.port, config_.state_dir);
}

bool SparkplugService::reload(const Config& loaded, const ConfigDiff& diff) {
  // The devices and their aliases are fixed for a session: other sensors, another session.
  // A node that could not start (its state_dir not writable) is tried again: fixing the folder
  // needs no restart.
  const bool off = node_ && !started_;
  if (!off && !diff.sparkplug_changed && sensor_names(loaded) == devices_) return false;
  if (node_) {
    node_->stop();
    retired_.add(std::move(node_));
  }
  config_ = loaded.sparkplug;
  make_node();
  start_as_user();
  return true;
}

void SparkplugService::stop() {
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
