// The MQTT feed (docs/northbound.md, "MQTT"): on the gateway's event loop, a timer takes a status copy,
// the publisher decides what is due into its bounded backlog, and the backlog is handed to the
// libmosquitto client while it is connected. The copy is taken between bus events and the
// network is the client's own thread's business, so neither a Modbus reply nor a bus
// transaction ever waits for the broker.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <memory>

#include "config/config.h"
#include "driver/expected.h"
#include "gateway/gateway_status.h"
#include "mqtt/mqtt_client.h"
#include "mqtt/mqtt_publisher.h"

namespace tiltgate {

class MqttFeed {
 public:
  MqttFeed(boost::asio::any_io_executor executor, StatusSource status, const MqttConfig& config);
  ~MqttFeed();

  Expected<Done, std::string> start();
  // Cancels the timer and sends "offline"; call before the event loop is stopped.
  void stop();
  MqttStats stats() const;

 private:
  void schedule();
  void tick();
  void flush();
  void report_drops(std::chrono::steady_clock::time_point now);

  boost::asio::steady_timer timer_;
  StatusSource status_;
  MqttPublisher publisher_;
  MqttClient client_;
  std::chrono::milliseconds period_;
  std::size_t backlog_capacity_;
  std::chrono::steady_clock::time_point started_at_{};
  bool warned_unreached_ = false;
  std::uint64_t published_ = 0;
  std::uint64_t connections_seen_ = 0;
  std::uint64_t drops_reported_ = 0;
  std::chrono::steady_clock::time_point drops_reported_at_{};
  bool running_ = false;
};

}  // namespace tiltgate
