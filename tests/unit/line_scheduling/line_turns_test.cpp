// LineTurns, the rule of a bus's line's turns (line_scheduling/line_turns.h), on its own: no Asio, no
// line; claims and times are made up. Then the rule run over a simulated line for a simulated
// hour, with sensors failing and clients writing, against the worst-case age that
// line_scheduling/line_budget.h promises.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <random>
#include <vector>

#include "line_scheduling/line_turns.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

const SteadyClock::time_point t0 = SteadyClock::time_point{} + 1h;

TurnClaim poll(std::chrono::milliseconds due, std::uint64_t order, bool failing = false) {
  TurnClaim claim;
  claim.kind = TurnKind::poll;
  claim.failing = failing;
  claim.due = t0 + due;
  claim.order = order;
  return claim;
}

TurnClaim other(TurnKind kind, std::uint64_t order, std::uint64_t client = 0) {
  TurnClaim claim;
  claim.kind = kind;
  claim.due = t0;
  claim.order = order;
  claim.client = client;
  return claim;
}

TurnClaim failing_retry(RetryAfter after, std::chrono::milliseconds due, std::uint64_t order) {
  TurnClaim claim = poll(due, order, true);
  claim.retry = after;
  return claim;
}

// `claims`, all ready at t0, in the order they get their turns.
std::vector<TurnClaim> served_in_order(std::vector<TurnClaim> claims) {
  LineTurns turns;
  std::vector<TurnClaim> served;
  while (!claims.empty()) {
    const TurnChoice choice = turns.choose(claims, t0);
    REQUIRE(choice.turn.has_value());
    served.push_back(claims[*choice.turn]);
    turns.ended(served.back(), t0);
    claims.erase(claims.begin() + std::ptrdiff_t(*choice.turn));
  }
  return served;
}

}  // namespace

TEST_CASE("line turns: with only polls waiting, the earliest due goes, and nothing due waits") {
  LineTurns turns;
  const std::vector<TurnClaim> claims{poll(30ms, 0), poll(10ms, 1), poll(20ms, 2)};
  const TurnChoice early = turns.choose(claims, t0);
  CHECK_FALSE(early.turn.has_value());
  REQUIRE(early.next_due.has_value());
  CHECK(*early.next_due == t0 + 10ms);
  const TurnChoice due = turns.choose(claims, t0 + 25ms);
  CHECK(due.turn == 1u);
  CHECK_FALSE(due.owed);
}

TEST_CASE("line turns: after another kind of turn, the polls that fell due by its end go first") {
  LineTurns turns;
  std::vector<TurnClaim> claims{poll(0ms, 0), other(TurnKind::write, 1), poll(0ms, 2)};
  CHECK(turns.choose(claims, t0 + 1ms).turn == 1u);  // the write, ahead of due polls
  turns.ended(claims[1], t0 + 50ms);
  claims[1] = other(TurnKind::write, 3);  // another write waits
  const TurnChoice next = turns.choose(claims, t0 + 50ms);
  CHECK(next.turn == 0u);  // the round's polls first
  CHECK(next.owed);
  claims.erase(claims.begin());
  CHECK(turns.choose(claims, t0 + 51ms).turn == 1u);  // the second poll
  claims.erase(claims.begin() + 1);
  CHECK(turns.choose(claims, t0 + 52ms).turn == 0u);  // then the write
}

TEST_CASE("line turns: a poll that falls due after the other turn ended waits for the next") {
  LineTurns turns;
  const TurnClaim write = other(TurnKind::write, 0);
  turns.ended(write, t0 + 50ms);
  const std::vector<TurnClaim> claims{poll(60ms, 1), other(TurnKind::write, 2)};
  CHECK(turns.choose(claims, t0 + 70ms).turn == 1u);
}

TEST_CASE("line turns: a failing sensor's attempt waits while the round's polls are owed, and is reported held") {
  LineTurns turns;
  const TurnClaim first = poll(0ms, 0, true);
  turns.ended(first, t0 + 500ms);  // its late-reply window
  const std::vector<TurnClaim> claims{poll(0ms, 1, true), poll(100ms, 2), poll(200ms, 3)};
  const TurnChoice choice = turns.choose(claims, t0 + 500ms);
  CHECK(choice.turn == 1u);
  CHECK(choice.held == 0u);
  // With the round done, the failing sensor is next even though a healthy poll is due.
  const std::vector<TurnClaim> after{poll(0ms, 1, true), poll(600ms, 2), poll(600ms, 3)};
  const TurnChoice next = turns.choose(after, t0 + 700ms);
  CHECK(next.turn == 0u);
  CHECK_FALSE(next.held.has_value());
}

TEST_CASE("line turns: writes, forwarded requests and failing sensors take turns by kind, the least recently served first") {
  LineTurns turns;
  std::vector<TurnClaim> claims{other(TurnKind::write, 0), other(TurnKind::forward, 1),
                                poll(0ms, 2, true)};
  std::vector<TurnKind> order;
  std::vector<bool> failing;
  for (int i = 0; i < 6; ++i) {
    const TurnChoice choice = turns.choose(claims, t0 + std::chrono::milliseconds(i));
    REQUIRE(choice.turn.has_value());
    const TurnClaim taken = claims[*choice.turn];
    order.push_back(taken.kind);
    failing.push_back(taken.failing);
    turns.ended(taken, t0 + std::chrono::milliseconds(i));
    claims[*choice.turn].order += 10;  // the same kind waits again
  }
  CHECK(order == std::vector<TurnKind>{TurnKind::write, TurnKind::forward, TurnKind::poll,
                                       TurnKind::write, TurnKind::forward, TurnKind::poll});
  CHECK(failing == std::vector<bool>{false, false, true, false, false, true});
}

TEST_CASE("line turns: a write waits for at most one failing sensor's attempt") {
  LineTurns turns;
  const TurnClaim failing = poll(0ms, 0, true);
  turns.ended(failing, t0);  // a failing attempt just ended: writes were served less recently
  const std::vector<TurnClaim> claims{poll(0ms, 1, true), poll(0ms, 2, true),
                                      other(TurnKind::write, 3)};
  CHECK(turns.choose(claims, t0 + 1ms).turn == 2u);
}

TEST_CASE("line turns: forwarded requests go round robin over their clients") {
  std::vector<std::uint64_t> clients;
  for (const TurnClaim& claim : served_in_order(
           {other(TurnKind::forward, 0, 7), other(TurnKind::forward, 1, 7),
            other(TurnKind::forward, 2, 7), other(TurnKind::forward, 3, 9),
            other(TurnKind::forward, 4, 3)}))
    clients.push_back(claim.client);
  // Each client in turn, however many requests the first one queued.
  CHECK(clients == std::vector<std::uint64_t>{3, 7, 9, 7, 7});
}

TEST_CASE("line turns: commands and forwarded requests take turns when both wait") {
  std::vector<TurnKind> kinds;
  for (const TurnClaim& claim :
       served_in_order({other(TurnKind::forward, 0), other(TurnKind::forward, 1),
                        other(TurnKind::command, 2), other(TurnKind::command, 3)}))
    kinds.push_back(claim.kind);
  CHECK(kinds == std::vector<TurnKind>{TurnKind::command, TurnKind::forward, TurnKind::command,
                                       TurnKind::forward});
}

TEST_CASE("line turns: among failing claims a retry after a garble goes first, then one after silence, then probes") {
  LineTurns turns;
  const std::vector<TurnClaim> claims{poll(0ms, 0, true),  // a probe, due first
                                      failing_retry(RetryAfter::silence, 5ms, 1),
                                      failing_retry(RetryAfter::garble, 9ms, 2)};
  CHECK(turns.choose(claims, t0 + 10ms).turn == 2u);
  const std::vector<TurnClaim> rest{claims[0], claims[1]};
  CHECK(turns.choose(rest, t0 + 10ms).turn == 1u);
}

// A line run on the rule alone, in simulated time: each turn lasts what its kind takes on a
// 9600-baud line of Rieker H6 with the defaults (a healthy poll 31 ms, a failing sensor's
// attempt with its late-reply window 531 ms, a short look 81 ms, a write 3 exchanges). Two
// sensors fall silent at the same moment, at random times; clients write to a healthy sensor
// all the time. No healthy sensor may go longer between two readings than the bound of
// line_scheduling/line_budget.h.
TEST_CASE("line turns: over a simulated hour, no healthy reading gets older than the line budget's bound") {
  using std::chrono::milliseconds;
  constexpr int kSensors = 10;
  constexpr milliseconds kPeriod{100}, kPoll{31}, kWindow{531}, kShortLook{81}, kWrite{93};
  std::mt19937 random(39);
  struct Sensor {
    SteadyClock::time_point due = t0;
    SteadyClock::time_point last_reading = t0;
    bool was_sick = false;  // since its last reading: that gap is not a healthy one
    int failures = 0;
  };
  std::vector<Sensor> sensors(kSensors);
  LineTurns turns;
  SteadyClock::time_point now = t0;
  std::uint64_t order = 0;
  std::map<int, std::uint64_t> orders;
  milliseconds worst{0};
  SteadyClock::time_point next_outage = t0 + 5s;
  std::uniform_int_distribution<int> pick(0, kSensors - 1);
  std::vector<int> sick;
  while (now < t0 + 1h) {
    // Two sensors fall silent at once; later they answer again, and once the line has found
    // both back, two others fall silent: never more than two failing.
    const bool recovered = std::all_of(sensors.begin(), sensors.end(),
                                       [](const Sensor& s) { return s.failures == 0; });
    if (now >= next_outage && !sick.empty()) {
      sick.clear();
      next_outage = now + std::chrono::seconds(5 + pick(random));
    } else if (now >= next_outage && recovered) {
      sick = {pick(random), pick(random)};
      while (sick[1] == sick[0]) sick[1] = pick(random);
      for (int s : sick) sensors[std::size_t(s)].was_sick = true;
      next_outage = now + std::chrono::seconds(5 + pick(random));
    }
    std::vector<TurnClaim> claims;
    for (int i = 0; i < kSensors; ++i) {
      const Sensor& s = sensors[std::size_t(i)];
      claims.push_back(poll(milliseconds(0), std::uint64_t(i), s.failures > 0));
      claims.back().due = s.due;
    }
    claims.push_back(other(TurnKind::write, 1000 + order++));  // always a write waiting
    claims.back().due = now;
    const TurnChoice choice = turns.choose(claims, now);
    if (!choice.turn) {
      now = *choice.next_due;
      continue;
    }
    const std::size_t index = *choice.turn;
    TurnClaim taken = claims[index];
    if (index == std::size_t(kSensors)) {
      now += kWrite;
      turns.ended(taken, now);
      continue;
    }
    Sensor& s = sensors[index];
    const bool silent = std::find(sick.begin(), sick.end(), int(index)) != sick.end();
    if (!silent) {
      now += kPoll;
      if (!s.was_sick)
        worst = std::max(worst, std::chrono::duration_cast<milliseconds>(now - s.last_reading));
      s.was_sick = false;
      s.last_reading = now;
      s.failures = 0;
      s.due = std::max(s.due + kPeriod, now);
    } else {
      // A sensor in good standing in a round after a long turn gives up early (a short look).
      now += !taken.failing && choice.owed ? kShortLook : kWindow;
      taken.failing = true;
      s.failures = std::min(s.failures + 1, 6);
      s.due = s.failures <= 2 ? now : now + kPeriod * (1 << (s.failures - 2));
    }
    turns.ended(taken, now);
  }
  // line_scheduling/line_budget.h: the line cannot keep up (R = 7 polls > poll_ms), so Q = R; two
  // failing, each with a short look, and one whole turn.
  const milliseconds bound = 7 * kPoll + (kWindow + 2 * kShortLook) + kPoll;
  CAPTURE(worst.count());
  CHECK(worst <= bound);
  CHECK(bound < 1000ms);  // inside stale_ms, as the issue asks of this line
}
