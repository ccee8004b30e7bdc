// A bus's line, shared among those who need it: the claimants (line_scheduling/line_claimant.h)
// waiting for it, the one holding it, and, whenever it is free, the next turn as the line's
// rule decides (line_scheduling/line_turns.h). It keeps a sensor's work in one piece (no one else's
// work for a sensor runs while a claimant is mid-way through its own), measures each turn (the
// line's busy time, and each sensor's share), and wakes at the next due time. BusScheduler
// (line_scheduling/bus_scheduler.h) owns one per bus. Everything runs on the buses' thread.
//
// Should choosing a turn ever fail (an exception: a bug, or memory), run() is told, never the
// claimant that happened to ask: it logs the failure at error, counts it (restarts()),
// refuses every write, forwarded request and command waiting (each is answered: a Modbus
// exception, an error line), and gives turns again after kRestartPause; the sensors' pollers
// keep their places.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <exception>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "driver/line.h"
#include "line_scheduling/gateway_sensor.h"
#include "line_scheduling/line_turns.h"

namespace tiltgate {

class LineClaimant;

class SharedLine {
 public:
  // `name`: the bus's, for the log.
  SharedLine(boost::asio::any_io_executor executor, Line& line, std::string name = "bus");
  // Stops (stop()) if it has not.
  ~SharedLine();
  SharedLine(const SharedLine&) = delete;
  SharedLine& operator=(const SharedLine&) = delete;

  // Gives the line out from now on (none before: a bus not started yet), and at each due time,
  // until stop(). Spawn it once.
  boost::asio::awaitable<void> run();
  // Everyone waiting is refused, and nobody touches this afterwards: the one holding the line
  // ends when the line's own stop() cancels its transaction.
  void stop();
  bool stopped() const { return stopping_; }
  // From now on only writes get the line (a bus a reload retires): the others waiting are
  // refused, and once no write is left, stop().
  void keep_only_writes();

  // A waiting claimant's claim now falls due at `due` (a command holds or releases a sensor).
  void reschedule(LineClaimant& claimant, SteadyClock::time_point due);
  // Ends a waiting claimant's wait: refused.
  void refuse(LineClaimant& claimant);

  // The forwarded requests waiting: how many, how many of them from `client`, and from how
  // many clients (`client` counted).
  struct ForwardsWaiting {
    std::size_t queued = 0;
    std::size_t from_client = 0;
    std::size_t clients = 1;
  };
  ForwardsWaiting forwards_waiting(std::uint64_t client) const;

  Line& line() { return line_; }
  boost::asio::any_io_executor executor() const { return executor_; }
  // Time the line was held, by anyone, waiting for replies and time-outs included.
  std::chrono::nanoseconds busy() const { return busy_; }
  // How often choosing a turn failed and run() started giving turns again.
  std::uint64_t restarts() const { return restarts_; }

  // After a failure, no turn is given for this long: a fault that repeats cannot spin.
  static constexpr std::chrono::seconds kRestartPause{1};
  // A failure is logged with its message at most this often; the count goes on.
  static constexpr std::chrono::seconds kFailureLogInterval{60};

  // Told when a failing sensor's claim waits while the round's polls go first (held to its
  // turn, line_scheduling/line_turns.h).
  std::function<void(const GatewaySensor&, SteadyClock::time_point)> on_held;

 private:
  friend class LineClaimant;

  // The claimants' side.
  void enqueue(LineClaimant& claimant);
  void withdraw(LineClaimant& claimant);
  void end_turn(LineClaimant& claimant);
  void disengage(LineClaimant& claimant);

  // Gives the line to whoever's turn it is, if it is free; with nobody's turn now, sets the
  // wake-up for the next due time. Never throws: a failure goes to run() (fail()).
  void dispatch();
  void choose_turn();
  void fail(std::exception_ptr failure);
  // run(), after a failure: logs and counts it, refuses all but the pollers, pauses, goes on.
  boost::asio::awaitable<void> restart();
  void grant(LineClaimant& claimant, bool failing, bool owed, SteadyClock::time_point now);
  // Whether `claimant`'s claim waits because another claimant is mid-way through its own
  // work for the same sensor.
  bool engaged_by_other(const LineClaimant& claimant) const;

  boost::asio::any_io_executor executor_;
  Line& line_;
  std::string name_;
  LineTurns turns_;
  std::vector<LineClaimant*> waiting_;  // in the order they came
  LineClaimant* holder_ = nullptr;      // holds the line now
  std::vector<LineClaimant*> engaged_;  // mid-way through their work for a sensor
  std::uint64_t next_order_ = 0;
  // dispatch()'s scratch: the claims it shows the rule, and whose they are.
  std::vector<TurnClaim> claims_;
  std::vector<LineClaimant*> claimants_;
  boost::asio::steady_timer wake_;  // run(): the next due time
  std::chrono::nanoseconds busy_{0};
  bool running_ = false;  // run() started
  bool stopping_ = false;
  bool only_writes_ = false;
  std::exception_ptr failure_;  // set by fail(), until run() restarted
  std::uint64_t restarts_ = 0;
  std::optional<SteadyClock::time_point> failure_logged_at_;
};

}  // namespace tiltgate
