// The MQTT feed (docs/northbound.md, "MQTT"): on the gateway's event loop, a timer takes a status
// copy, the publisher decides what is due, and that goes to the libmosquitto client while it is
// connected; what it could not send (the broker away, or a connection lost before the
// broker acknowledged it) goes to the backlog, on disk in <state_dir>/mqtt/ (mqtt/mqtt_backlog.h),
// which is replayed after the live messages of each tick once the broker is back
// (mqtt/backlog_replay.h). The copy is taken between bus events and the network is the client's
// own thread's business, so neither a Modbus reply nor a bus transaction ever waits for the
// broker.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <memory>

#include "config/config.h"
#include "driver/expected.h"
#include "gateway/gateway_status.h"
#include "mqtt/backlog_replay.h"
#include "mqtt/mqtt_backlog.h"
#include "mqtt/mqtt_client.h"
#include "mqtt/mqtt_publisher.h"
#include "mqtt/unacknowledged_messages.h"

namespace tiltgate {

class MqttFeed {
 public:
  // `events`: the monitoring's, published from those after the newest at start() (empty
  // functions: none).
  MqttFeed(boost::asio::any_io_executor executor, StatusSource status, const MqttConfig& config,
           MqttEventSource events = {});
  ~MqttFeed();

  Expected<Done, std::string> start();
  // Cancels the timer, sends "offline", keeps what was not acknowledged and closes the
  // backlog (a feed made by a reload opens it again); call before the event loop is stopped.
  void stop();
  MqttStats stats() const;
  // Stopped: its client's thread has ended and its timer's handler has run (cancelling does not
  // take back a handler the timer's expiry already queued), so a reload that replaced it may
  // free it.
  bool finished() const { return !running_ && !tick_waiting_; }

 private:
  using Clock = std::chrono::steady_clock;

  void schedule();
  void tick();
  void open_backlog();
  // A state directory that could not be used at the start, tried again; the messages held in
  // memory meanwhile move to it.
  void retry_state_dir(Clock::time_point now);
  void take_acknowledgements();
  void keep_unacknowledged();
  void send_or_keep(MqttMessage message);
  // The events since the last tick, on <prefix>/events, and the bursts' batches, on
  // <prefix>/<sensor>/burst.
  void publish_events();
  void keep(const MqttMessage& message);
  void replay();
  void sync_backlog(Clock::time_point now);
  void report_drops(Clock::time_point now);
  void report_notices();
  void report_backlog_error(const std::string& error);

  boost::asio::steady_timer timer_;
  bool tick_waiting_ = false;  // the timer's handler is still to run
  StatusSource status_;
  MqttEventSource events_;
  std::uint64_t events_sent_ = 0;  // the last event's number handed to the client or the backlog
  std::uint64_t bursts_sent_ = 0;  // the same for the bursts' batches
  MqttConfig config_;
  MqttPublisher publisher_;
  MqttClient client_;
  // Opened at the first tick, on the event loop: as the user the gateway serves as
  // ([server] user), so the files are that user's.
  std::unique_ptr<MqttBacklog> backlog_;
  UnacknowledgedMessages unacknowledged_;
  BacklogReplay replay_;
  std::chrono::milliseconds period_;
  Clock::time_point started_at_{};
  bool warned_unreached_ = false;
  std::uint64_t published_ = 0;
  std::uint64_t connections_seen_ = 0;
  std::uint64_t drops_reported_ = 0;
  Clock::time_point drops_reported_at_{};
  Clock::time_point synced_at_{};
  Clock::time_point error_logged_at_{};
  bool store_unused_ = false;  // the backlog is in memory for want of the state directory
  Clock::time_point store_tried_at_{};
  StoreStats memory_counts_;  // dropped and replayed while it was in memory
  bool running_ = false;
};

}  // namespace tiltgate
