// Who transmits on the lines of a redundant pair, one master at a time (docs/operations.md,
// "Warm standby"). Every gateway of a pair starts listening: each bus's tty is opened
// receive-only (capture/line_listener.h) and what the active master asks and the sensors
// answer goes to the bus's HeardExchanges, from which its pollers serve every unit warm
// (BusScheduler::listen_to()). It takes the lines when no request has been heard on any of
// them for takeover_ms (a primary's wait is half of it, so one starting beside its standby goes
// first; silence_needed()) and the peer does not answer as the active one; then the buses' lines open as
// usual and the listeners close. An active gateway stands down at once, back to listening, when
// its MasterGuard hears another master's request before one of its own, when it was stalled
// for half the takeover time, and when one of its lines has been closed (an unplugged adapter)
// for half the takeover time while the peer answers. With failback, an active standby gives the
// lines back when its peer, the primary, answers as listening.
//
// Runs on the gateway's event loop. The gateway adds its buses before start(), and as a
// reload makes or retires them.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "capture/line_listener.h"
#include "config/config.h"
#include "gateway/gateway_status.h"
#include "redundancy/heard_exchanges.h"
#include "redundancy/master_guard.h"
#include "redundancy/peer_probe.h"

namespace tiltgate {

class BusScheduler;
class SerialLine;

// A bus as the controller switches it: its line, its scheduler, how to listen to it.
struct RedundantBus {
  std::string name;
  SerialLine* line = nullptr;
  BusScheduler* scheduler = nullptr;
  // The tty to listen to; none: a bus behind a device server, which allows one client: it is
  // opened only while this gateway is active.
  std::optional<LineListenerOptions> listening{};
  std::chrono::nanoseconds character_time{0};
};

class RedundancyController {
 public:
  using Clock = std::chrono::steady_clock;
  // Called as the gateway takes the lines (true) or gives them up (false): the feeds that must
  // come from one gateway of the pair (MQTT, Sparkplug) start and stop with it.
  using RoleChanged = std::function<void(bool active)>;

  RedundancyController(boost::asio::any_io_executor executor, RedundancyConfig config,
                       PeerProbe probe);
  ~RedundancyController();
  RedundancyController(const RedundancyController&) = delete;
  RedundancyController& operator=(const RedundancyController&) = delete;

  void on_role_change(RoleChanged changed) { role_changed_ = std::move(changed); }
  // A bus to switch, from now on in the gateway's present role (a reload's new bus included).
  void add_bus(RedundantBus bus);
  // A bus a reload retired: no longer listened to.
  void remove_bus(const BusScheduler* scheduler);
  // Starts listening and watching; the first add_bus() posts it, so it runs once the gateway
  // has added all the buses it starts with.
  void start();
  // Ends every wait and listener (the gateway stops).
  void stop();

  bool active() const { return active_; }
  RedundancyStatus status() const;

  // The controller looks at the lines this often.
  static constexpr std::chrono::milliseconds kTick{20};

 private:
  struct Bus {
    RedundantBus config;
    std::shared_ptr<HeardExchanges> heard;
    std::unique_ptr<LineListener> listener;
    std::unique_ptr<MasterGuard> guard;
    bool line_started = false;
    std::optional<Clock::time_point> closed_since;  // active: its line has been closed since
    std::optional<Clock::time_point> listen_failed_logged;
  };

  boost::asio::awaitable<void> watch();
  // Asks the peer, then takes the lines or gives them up as the answer and the lines say.
  boost::asio::awaitable<void> ask_and_decide();
  // Active: why a line closed for half the takeover time should go to the peer, if one is.
  std::optional<std::string> due_closed_line(Clock::time_point now);
  // Active standby with failback: time to ask whether the primary is back.
  bool failback_due(Clock::time_point now) const;
  boost::asio::awaitable<void> keep_listening(std::shared_ptr<Bus> bus);
  void listen(Bus& bus);
  void transmit(Bus& bus);
  void take_over(std::string why);
  void stand_down(std::string why);
  // Standby: the last request heard on any line, or when listening began.
  Clock::time_point last_heard() const;
  // The silence after which this gateway may take the lines.
  std::chrono::milliseconds silence_needed() const;

  boost::asio::any_io_executor executor_;
  RedundancyConfig config_;
  PeerProbe probe_;
  RoleChanged role_changed_;
  std::vector<std::shared_ptr<Bus>> buses_;
  boost::asio::steady_timer tick_;
  bool started_ = false;
  bool start_posted_ = false;
  bool stopped_ = false;
  bool active_ = false;
  bool probing_ = false;
  Clock::time_point listening_since_{};
  double since_unix_ = 0;
  std::string reason_;
  std::uint64_t takeovers_ = 0;
  std::uint64_t step_downs_ = 0;
  std::optional<Clock::time_point> last_tick_;
  std::optional<Clock::time_point> last_failback_probe_;
  bool peer_active_logged_ = false;
};

}  // namespace tiltgate
