// The Sparkplug B edge node at work (docs/northbound.md, "Sparkplug B"): the session rules
// (sparkplug/edge_node_session.h) driven from the gateway's event loop, with the sensors'
// samples every 100 ms, the libmosquitto client (mqtt/mqtt_client.h) on its own network
// thread, bdSeq kept in state_dir, the DDATA kept on disk while the broker is away and
// replayed after the births, and DCMD setting writes on the sensors' buses.
//
// Threads: every session call is made on the event loop. The client's hooks run on its
// network thread and post there; before a CONNECT the network thread waits for the loop's
// will (begin_connect) and its bdSeq on disk. A DCMD's write goes through the settings room's
// writer (settings/setting_writer.h), as the console's do.
#pragma once

#include <atomic>
#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "clock/clock_state.h"
#include "config/config.h"
#include "driver/expected.h"
#include "gateway/gateway.h"
#include "gateway/gateway_status.h"
#include "doors/log_throttle.h"
#include "doors/request_rate.h"
#include "mqtt/mqtt_client.h"
#include "monitoring/burst_feed.h"
#include "sparkplug/ddata_backlog.h"
#include "sparkplug/device_sampler.h"
#include "sparkplug/edge_node_session.h"
#include "settings/setting_writer.h"

namespace tiltgate::sparkplug {

// At most this many kept DDATA are replayed per 100 ms tick (500 a second): after the tick's
// live data, so a long backlog never delays it.
inline constexpr std::size_t kReplayPerTick = 50;

class EdgeNode {
 public:
  // `clock`: the system clock's state, its NBIRTH's and NDATA's Clock/ metrics. `bursts`: the
  // monitoring's bursts, each batch after the newest at start() kept for the store-and-forward
  // as historical DDATA (empty functions: none).
  EdgeNode(boost::asio::any_io_executor executor, const Gateway& gateway, FamilyList families,
           const SparkplugConfig& config, ClockReader clock,
           monitoring::BurstSource bursts = {});
  ~EdgeNode();
  EdgeNode(const EdgeNode&) = delete;
  EdgeNode& operator=(const EdgeNode&) = delete;

  // Opens state_dir (created if missing: an error when it cannot be created or written), reads
  // the last bdSeq and starts the client, which connects on its own. `last_bd_seq`: that of the
  // edge node this process ran before this one (its last_bd_seq()), taken over the stored one,
  // which is older when the disk refused to store it.
  Expected<Done, std::string> start(std::optional<std::uint8_t> last_bd_seq);
  // NDEATH and a clean DISCONNECT when connected; call before the event loop is stopped.
  void stop();

  // The bdSeq of its last will (whose CONNECT may not have gone out), else the one it started
  // from: the next edge node of the process goes on from it.
  std::optional<std::uint8_t> last_bd_seq() const { return last_bd_seq_; }
  SparkplugStats stats() const;
  std::optional<StoreStats> store_stats() const;
  // Stopped, and no DCMD write of its is still waiting for its sensor's bus: nothing refers to
  // it any more, so a reload that replaced it may free it.
  bool finished() const;

 private:
  void schedule();
  void tick();
  void carry_out(std::vector<Action> actions);
  // The bursts' batches since the last tick, kept as historical DDATA (burst_metrics()): the
  // store-and-forward replays them after the live data, in order, once the device is born.
  void keep_bursts();
  bool publish(const Publish& message);  // false: not connected
  void write_setting(Write write);
  void log_refusal_summaries();
  Instant now() const;
  // On the network thread, before each CONNECT.
  std::optional<MqttWill> prepare_connect();
  // On the event loop: the will of the next CONNECT, its bdSeq stored first.
  std::optional<MqttWill> begin_connect();
  template <class Handler>
  void post(Handler handler);

  boost::asio::any_io_executor executor_;
  boost::asio::steady_timer timer_;
  bool tick_waiting_ = false;  // the timer's handler is still to run
  const Gateway& gateway_;
  const SparkplugConfig config_;
  ClockReader clock_;
  monitoring::BurstSource bursts_;
  std::uint64_t bursts_kept_ = 0;  // the last batch's number handed to the store
  std::filesystem::path dir_;  // state_dir/sparkplug
  DeviceSampler sampler_;
  SettingWriter writer_;
  std::optional<EdgeNodeSession> session_;
  std::optional<DdataBacklog> backlog_;
  std::unique_ptr<MqttClient> client_;
  // False once stop() began: posted handlers then leave the session alone, and a CONNECT
  // waiting for its will gives up.
  std::shared_ptr<std::atomic<bool>> alive_ = std::make_shared<std::atomic<bool>>(true);
  bool running_ = false;
  std::chrono::steady_clock::time_point started_at_{};
  bool warned_unreached_ = false;
  std::uint64_t ticks_ = 0;
  std::uint64_t published_ = 0;
  std::uint64_t writes_refused_ = 0;
  // [sparkplug] max_commands_per_s, taken on the client's network thread, and what waited.
  SharedRateLimit command_rate_;
  std::atomic<std::uint64_t> commands_delayed_ = 0;
  std::chrono::steady_clock::time_point malformed_logged_at_{};
  std::size_t writes_in_flight_ = 0;
  LogThrottle refusal_log_;  // per sensor
  std::chrono::steady_clock::time_point store_error_logged_at_{};
  std::chrono::steady_clock::time_point bd_seq_error_logged_at_{};
  std::optional<std::uint8_t> stored_bd_seq_;  // what state_dir's bdSeq file holds
  std::optional<std::uint8_t> last_bd_seq_;    // of the last will, else what start() began from
  std::uint64_t drops_logged_ = 0;
  std::chrono::steady_clock::time_point drops_logged_at_{};
};

}  // namespace tiltgate::sparkplug
