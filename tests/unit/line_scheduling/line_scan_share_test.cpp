// A scan on a line in service: a commissioning command's transactions take the line's spare
// time (line_scheduling/line_turns.h, rule 2), and a poll a probe held up is made up for
// (line_scheduling/poll_schedule.h). First the rule on made-up claims, then a line run on the rule and
// the poll schedule alone, in simulated time, with a scan probing silent addresses throughout.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "line_scheduling/line_turns.h"
#include "line_scheduling/poll_schedule.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

const SteadyClock::time_point t0 = SteadyClock::time_point{} + 1h;

// A claim of `kind`: a poll due at `due`, or anything else waiting since then.
TurnClaim claim_of(TurnKind kind, SteadyClock::time_point due, std::uint64_t order) {
  TurnClaim claim;
  claim.kind = kind;
  claim.due = due;
  claim.order = order;
  return claim;
}

TurnClaim poll_at(SteadyClock::time_point due, std::uint64_t order) {
  return claim_of(TurnKind::poll, due, order);
}

TurnClaim command_since(SteadyClock::time_point came, std::uint64_t order) {
  return claim_of(TurnKind::command, came, order);
}

}  // namespace

TEST_CASE("line turns: a command's transaction goes at once on a line with no healthy poll waiting") {
  LineTurns turns;
  turns.ended(command_since(t0, 0), t0 + 33ms, 33ms);
  TurnClaim failing = poll_at(t0 + 40ms, 1);
  failing.failing = true;  // an offline sensor's next probe is no healthy poll
  const std::vector<TurnClaim> claims{command_since(t0, 2), failing};
  CHECK(turns.choose(claims, t0 + 33ms).turn == 0u);
}

TEST_CASE("line turns: a command's transaction goes when it fits before the next healthy poll") {
  LineTurns turns;
  turns.ended(command_since(t0, 0), t0 + 33ms, 33ms);
  const std::vector<TurnClaim> claims{poll_at(t0 + 80ms, 1), command_since(t0, 2)};
  CHECK(turns.choose(claims, t0 + 40ms).turn == 1u);  // 40 + 33 < 80
}

TEST_CASE("line turns: a command's transaction that does not fit waits for its share of the line") {
  LineTurns turns;
  turns.ended(command_since(t0, 0), t0 + 33ms, 33ms);
  // A poll falls due within the command's length: not before 9 x 33 ms after the last ended.
  const std::vector<TurnClaim> claims{poll_at(t0 + 50ms, 1), command_since(t0, 2)};
  const TurnChoice waits = turns.choose(claims, t0 + 40ms);
  CHECK_FALSE(waits.turn.has_value());
  REQUIRE(waits.next_due.has_value());
  CHECK(*waits.next_due == t0 + 50ms);  // the poll's turn comes first
  // Due polls go ahead of it...
  const std::vector<TurnClaim> due{poll_at(t0 + 50ms, 1), command_since(t0, 2)};
  CHECK(turns.choose(due, t0 + 60ms).turn == 0u);
  // ... and with nothing else to do, the line wakes for it when its share comes.
  const std::vector<TurnClaim> later{poll_at(t0 + 332ms, 1), command_since(t0, 2)};
  const TurnChoice wake = turns.choose(later, t0 + 300ms);
  CHECK_FALSE(wake.turn.has_value());
  REQUIRE(wake.next_due.has_value());
  CHECK(*wake.next_due == t0 + 33ms + 9 * 33ms);
  CHECK(turns.choose(due, t0 + 33ms + 9 * 33ms).turn == 1u);  // its share: ahead of a due poll
}

TEST_CASE("line turns: a command never waits longer than kCommandMaxWait for its share") {
  LineTurns turns;
  turns.ended(command_since(t0, 0), t0 + 600ms, 600ms);  // a probe with a long late window
  // A poll that fell due after it (the round owes none): it goes while the command waits.
  const std::vector<TurnClaim> claims{poll_at(t0 + 700ms, 1), command_since(t0, 2)};
  CHECK(turns.choose(claims, t0 + 600ms + LineTurns::kCommandMaxWait - 1ms).turn == 0u);
  CHECK(turns.choose(claims, t0 + 600ms + LineTurns::kCommandMaxWait).turn == 1u);
}

TEST_CASE("line turns: a forwarded request is not held back by a command waiting for its share") {
  LineTurns turns;
  turns.ended(command_since(t0, 0), t0 + 33ms, 33ms);
  const TurnClaim forward = claim_of(TurnKind::forward, t0, 3);
  const std::vector<TurnClaim> claims{poll_at(t0 + 50ms, 1), command_since(t0, 2), forward};
  CHECK(turns.choose(claims, t0 + 40ms).turn == 2u);
}

namespace {

struct Carried {
  int polls = 0;
  int probes = 0;
};

// What a line of `sensors` sensors polled every `period` (each poll `poll` long) carries in
// `span` of simulated time, with a scan's probes of `probe` each always waiting when `scan`.
// Polls are answered; their schedule is the gateway's (after_poll).
Carried carried(int sensors, std::chrono::milliseconds period, std::chrono::microseconds poll,
                  std::chrono::milliseconds probe, bool scan, std::chrono::seconds span) {
  std::vector<PollSchedule> schedules(std::size_t(sensors), PollSchedule{t0});
  LineTurns turns;
  SteadyClock::time_point now = t0;
  std::uint64_t order = 0;
  Carried line;
  while (now < t0 + span) {
    std::vector<TurnClaim> claims;
    for (std::size_t i = 0; i < schedules.size(); ++i)
      claims.push_back(poll_at(schedules[i].due, i));
    if (scan) claims.push_back(command_since(now, 1000 + order++));
    const TurnChoice choice = turns.choose(claims, now);
    if (!choice.turn) {
      now = *choice.next_due;
      continue;
    }
    const std::size_t index = *choice.turn;
    const SteadyClock::time_point start = now;
    if (claims[index].kind == TurnKind::command) {
      now += probe;
      ++line.probes;
    } else {
      now += poll;
      schedules[index] = after_poll(schedules[index], true, period, 5s, now);
      ++line.polls;
    }
    turns.ended(claims[index], now, now - start);
  }
  return line;
}

}  // namespace

// The bench's line (bench/console_load.py): ten H6 at poll_ms = 50 on 125000 baud (a poll about
// 2.6 ms: the line about half used), and a scan of silent addresses, each probe a 13 ms
// time-out and 20 ms of quiet. Before, the probes took half the line and the polls 0.95 of
// their idle rate.
TEST_CASE("a scan on a half-used line leaves the sensors at least 0.99 of their idle polls") {
  const int idle = carried(10, 50ms, 2600us, 33ms, false, 60s).polls;
  const Carried scan = carried(10, 50ms, 2600us, 33ms, true, 60s);
  CAPTURE(idle);
  CAPTURE(scan.polls);
  CHECK(idle >= 11990);  // 200 polls/s
  CHECK(double(scan.polls) / idle >= 0.99);
  CHECK(scan.probes >= 60 * 3);  // the scan goes on: at least its tenth of the line
}

TEST_CASE("a scan on a saturated line takes at most about a tenth of it") {
  const int idle = carried(10, 10ms, 2600us, 33ms, false, 60s).polls;
  const Carried scan = carried(10, 10ms, 2600us, 33ms, true, 60s);
  CAPTURE(idle);
  CAPTURE(scan.polls);
  CHECK(double(scan.polls) / idle >= 0.89);
  CHECK(scan.probes >= 60 * 3);  // the scan still gets its share
}
