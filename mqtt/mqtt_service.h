// The MQTT feed ([mqtt], mqtt/mqtt_feed.h) as a service attached to the gateway
// (gateway/gateway_service.h): made when the table is there, restarted when a reload changes
// it, and paused while the gateway is the standby of a redundant pair.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <memory>
#include <optional>

#include "config/config.h"
#include "gateway/gateway_service.h"
#include "gateway/gateway_status.h"
#include "gateway/retired.h"
#include "mqtt/mqtt_feed.h"

namespace tiltgate {

class MqttService final : public GatewayService {
 public:
  MqttService(boost::asio::any_io_executor executor, StatusSource status, const MqttConfig& config,
              MqttEventSource events = {});
  ~MqttService() override;

  // Nothing before the switch to [server] user: the backlog's files are that user's.
  void start() override {}
  void start_as_user() override;
  bool reload(const Config& loaded, const ConfigDiff& diff) override;
  void stop() override;
  std::string_view name() const override { return "mqtt"; }

  // On a redundant pair only the active gateway feeds the broker (app/served_gateway.cpp):
  // pause() stops the feed ("offline", what was not acknowledged kept in the backlog) and
  // keeps it from starting, at start-up and at a reload alike, which then only take the new
  // table; resume() starts a new feed, as a reload does, since a stopped one does not start
  // again (its backlog closed). Not before start_as_user(): the backlog's files are the serving
  // user's.
  void pause();
  void resume();

  // The feed's counters; none while [mqtt] is off or the feed is paused.
  std::optional<MqttStats> stats() const;

 private:
  void make_feed();
  void retire_feed();

  boost::asio::any_io_executor executor_;
  StatusSource status_;
  MqttEventSource events_;
  MqttConfig config_;
  std::unique_ptr<MqttFeed> feed_;  // none without [mqtt], and while paused
  bool paused_ = false;
  // Feeds a reload replaced, freed (their client's socket with them) once stopped.
  Retired<MqttFeed> retired_;
};

}  // namespace tiltgate
