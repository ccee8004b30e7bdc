// Whose turn a bus's line is next: the one rule by which a bus shares its line's time among its
// sensors' polls, Modbus writes, requests forwarded to devices it passes through, commissioning
// commands' transactions and failing sensors. Pure: BusScheduler (line_scheduling/bus_scheduler.h)
// says who waits and for what, asks choose(), runs the turn, and says when it ended(). No Asio.
//
// 1. Rounds. A healthy sensor's poll is owed once it falls due before the last other turn
//    ended: after any turn that is not a healthy poll (a write, a forwarded request, a
//    command's transaction, a failing sensor's attempt), every poll that fell due by then goes
//    first, earliest due first. A healthy sensor so waits for at most one such turn and one
//    poll of each other healthy sensor before its own (docs/operations.md, "One failing sensor
//    never takes its line").
// 2. Between rounds, the other turns in rotation by kind: writes (first come, first served),
//    forwarded requests and commands' transactions (taking turns when both wait; forwarded
//    requests round robin over the clients that sent them), and failing sensors' attempts
//    (earliest due first). The kind that had a turn least recently goes first, so none starves
//    another, and a write waits for at most one failing sensor's attempt.
//    A command's transaction (a scan's probe, mostly: a time-out and a late-reply window) takes
//    the line's spare time: it goes when it fits before the next healthy poll falls due (as
//    long as the last command's turn took), and otherwise once the line has run
//    kLineTimePerCommandTime times that turn since it ended (at most kCommandMaxWait), so
//    commissioning takes at most a tenth of a line its polls keep busy, and a scan leaves the
//    sensors their polls (docs/operations.md, "Scanning a line in service").
// 3. Otherwise healthy polls that are due, earliest first (on a saturated bus: round robin).
//
// A claim is failing when its sensor is offline (its probes come at the back-off's pace),
// answers late, or is between two attempts of one exchange: each of a failing claim's attempts
// is a turn of its own (line_scheduling/line_claimant.h), so its time-outs and late-reply guards are
// spread over the rounds instead of served back to back. Among failing claims a retry after a
// garbled reply goes first (its device answers: most likely noise), then a retry after silence,
// then probes and late sensors' polls; earliest due first within each.
//
// A turn chosen by rule 1 is `owed`: the sensors waiting in that round have already waited out
// one long turn, so a healthy sensor that falls silent in it gives the line up after a short
// look instead of its whole late-reply window (serial/serial_line.h; its own next attempt
// still waits for the window). A neighbour's wait so holds at most one whole window.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>

#include "driver/sensor_state.h"

namespace tiltgate {

enum class TurnKind : std::uint8_t { poll, write, forward, command };

// What a failing claim retries after, which orders failing claims.
enum class RetryAfter : std::uint8_t { garble, silence, nothing };

// One who waits for the line, as the rule sees it.
struct TurnClaim {
  TurnKind kind = TurnKind::poll;
  bool failing = false;
  RetryAfter retry = RetryAfter::nothing;
  SteadyClock::time_point due{};  // a poll: when it falls due; anything else: when it came
  std::uint64_t client = 0;       // a forwarded request: who sent it (round robin)
  std::uint64_t order = 0;        // when it came: first come, first served among equals
};

struct TurnChoice {
  std::optional<std::size_t> turn;  // the claim whose turn it is now
  bool owed = false;                // a poll the round owes (rule 1)
  // Nothing's turn now: when the earliest claim falls due (none: nothing waits).
  std::optional<SteadyClock::time_point> next_due;
  // A failing claim that is ready but waits while the round's polls go first.
  std::optional<std::size_t> held;
};

class LineTurns {
 public:
  // The turn among `claims` at `now`.
  TurnChoice choose(std::span<const TurnClaim> claims, SteadyClock::time_point now) const;
  // `claim`'s turn ended at `end`, after holding the line for `held`.
  void ended(const TurnClaim& claim, SteadyClock::time_point end,
             SteadyClock::duration held = SteadyClock::duration::zero());

  // A command's transaction that does not fit before the next healthy poll waits until the
  // line has run this many times its last turn since that ended (rule 2)...
  static constexpr int kLineTimePerCommandTime = 9;
  // ... but never longer than this (a long late-reply window at a low baud rate).
  static constexpr std::chrono::milliseconds kCommandMaxWait{2000};

 private:
  // The kinds of turn that take turns between rounds (rule 2), in the order that breaks ties.
  enum Other : std::uint8_t { write, exchange, failing, other_kinds };
  static std::optional<Other> other_of(const TurnClaim& claim);
  // When a command's transaction may have the line, healthy polls first falling due at
  // `next_poll` (none: no healthy poll waits); no later than `now` when it may now.
  SteadyClock::time_point command_allowed_at(std::optional<SteadyClock::time_point> next_poll,
                                             SteadyClock::time_point now) const;

  // Polls due by this time are owed before the next turn of another kind (rule 1).
  SteadyClock::time_point round_until_ = SteadyClock::time_point::min();
  std::array<std::uint64_t, other_kinds> last_turn_{};  // per kind: the turn it last had
  std::uint64_t turns_ = 0;
  bool command_last_ = false;      // of the exchanges, the last was a command's
  SteadyClock::time_point command_ended_ = SteadyClock::time_point::min();  // the last command's
  SteadyClock::duration command_held_ = SteadyClock::duration::zero();      // turn, and its length
  std::uint64_t last_client_ = 0;  // whose forwarded request went last
};

}  // namespace tiltgate
