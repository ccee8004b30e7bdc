// One who needs a bus's line: a sensor's poller, a Modbus write, a request forwarded to a
// device passed through, or a commissioning command's transaction. It waits for its turn
// (line_scheduling/shared_line.h grants them as line_scheduling/line_turns.h decides) and, holding it, is the Line its
// work runs on: each transaction goes to the bus's line, but before an attempt after one that
// timed out, and before every attempt but the first of a failing sensor's, it gives the line
// back and waits for a failing sensor's turn, so its time-outs and late-reply guards take
// their turns with the other sensors' polls instead of holding the line back to back.
//
// A request's retries (-1: the line's) are made here, one attempt a turn. Drivers make their
// own (driver/polled_sensor_driver.h) and pass retries = 0, so each attempt comes as a
// transaction of its own here, with their adapted reply wait.
//
// With a deadline (a write's write_timeout_ms, a forwarded request's, a command's), no
// attempt is sent that the line could hold past it (Line::longest_attempt()): the transaction
// returns LineError::expired instead, and a wait for the first turn that could no longer end
// in time ends as expired.
//
// Threads: the buses' thread only.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <optional>

#include "driver/line.h"
#include "line_scheduling/gateway_sensor.h"
#include "line_scheduling/line_turns.h"

namespace tiltgate {

class SharedLine;

// How a wait for the line ended.
enum class TurnGrant : std::uint8_t {
  granted,
  refused,  // the bus stops, or retires (or removed the sensor polled)
  expired,  // its deadline came first
};

class LineClaimant final : public Line {
 public:
  // `sensor`: whose work it is (none for forwarded requests and commands), kept engaged from
  // the first turn until finish(): no one else's work for it runs in between.
  LineClaimant(SharedLine& line, TurnKind kind, GatewaySensor* sensor,
               std::optional<SteadyClock::time_point> deadline, std::uint64_t client = 0);
  // Gives back the line, or its place among those waiting.
  ~LineClaimant() override;
  LineClaimant(const LineClaimant&) = delete;
  LineClaimant& operator=(const LineClaimant&) = delete;

  // Waits for the line. `due`: not before then (a poll's schedule); now by default.
  boost::asio::awaitable<TurnGrant> wait_turn(
      std::optional<SteadyClock::time_point> due = std::nullopt);
  // The work is done: the line goes to whoever is next. The claimant may wait again.
  void finish();
  // Waiting for a turn; and for one between two attempts of its work; and for one to retry
  // after an attempt its device did not answer (silent or garbled).
  bool waiting() const { return state_ == State::waiting; }
  bool between_attempts() const { return yielded_; }
  bool retrying() const { return yielded_ && claim_.retry != RetryAfter::nothing; }

  boost::asio::awaitable<Expected<Done, LineError>> transact(LineRequest request) override;
  std::uint64_t generation() const override;
  bool is_open() const override;
  int retries() const override;
  const std::string& name() const override;
  const LineStats& stats() const override;
  // The last transaction's timing, over its attempts.
  const LineTiming& last_timing() const override { return timing_; }
  std::chrono::milliseconds longest_attempt(std::chrono::milliseconds timeout,
                                            std::size_t request_bytes) const override;
  std::chrono::seconds frames_kept() const override;

 private:
  friend class SharedLine;
  enum class State : std::uint8_t { idle, waiting, holding, detached };

  // Gives the line back between two attempts of `request` and waits for a failing turn.
  boost::asio::awaitable<TurnGrant> wait_again(const LineRequest& request);
  boost::asio::awaitable<TurnGrant> wait(std::optional<SteadyClock::time_point> expiry);
  // Whether an attempt of `request` could end before the deadline if sent now.
  bool attempt_fits(const LineRequest& request) const;

  SharedLine* shared_;  // null once the line stopped: nothing of it is touched then
  Line& line_;          // the bus's own
  GatewaySensor* sensor_;
  std::optional<SteadyClock::time_point> deadline_;
  // failing: as it was when its turn was granted, or since an attempt in it timed out.
  TurnClaim claim_;
  State state_ = State::idle;
  std::optional<TurnGrant> outcome_;  // set when a wait ends
  bool engaged_ = false;    // its sensor is engaged by it (from its first turn to finish())
  bool yielded_ = false;    // waits between two attempts: a failing turn
  bool yield_next_ = false; // the next attempt needs a turn of its own
  bool owed_ = false;       // this turn is a round's owed poll (line_scheduling/line_turns.h)
  SteadyClock::time_point turn_started_{};
  boost::asio::steady_timer wake_;  // cancelled when the wait ends
  LineTiming timing_;
};

}  // namespace tiltgate
