// What one poll came to, from the sensor's state before and after it: a refusal is an answer,
// told apart from silence, and an old reading is not a new one.
#include <doctest/doctest.h>

#include "commission/poll_outcome.h"
#include "commission/reading_format.h"

using namespace tiltgate;

namespace {

SensorState with_reading(std::uint16_t seq) {
  SensorState state;
  state.online = true;
  state.reading = Reading{};
  state.sample_seq = seq;
  return state;
}

}  // namespace

TEST_CASE("a poll that brought a new reading is a reading") {
  const SensorState before;
  CHECK(outcome_since(mark_before_poll(before), with_reading(1)).result == PollResult::reading);
  CHECK(outcome_since(mark_before_poll(with_reading(4)), with_reading(5)).result ==
        PollResult::reading);
}

TEST_CASE("a NAK to the measurement is a refusal with its code, not silence") {
  SensorState state = with_reading(7);
  const PollMark before = mark_before_poll(state);
  ++state.counters.refusals[2];
  state.counters.last_refusal = 2;
  const PollOutcome outcome = outcome_since(before, state);
  CHECK(outcome.result == PollResult::refused);
  CHECK(outcome.refusal == 2);
  CHECK(status_word(outcome.result) == "refused");
}

TEST_CASE("a refusal code past the counted ones still counts as a refusal when it is new") {
  SensorState state;
  state.online = true;
  const PollMark before = mark_before_poll(state);
  state.counters.last_refusal = 0xFF;  // a malformed NAK: not counted by code
  CHECK(outcome_since(before, state).result == PollResult::refused);
}

TEST_CASE("a poll with no valid reply is silence, an old reading does not make it a reading") {
  SensorState state = with_reading(3);
  const PollMark before = mark_before_poll(state);
  state.online = false;
  CHECK(outcome_since(before, state).result == PollResult::silent);
  CHECK(status_word(PollResult::silent) == "no-reply");
}

TEST_CASE("an answer that is neither a reading nor a refusal is no reading") {
  SensorState state = with_reading(3);
  const PollMark before = mark_before_poll(state);
  CHECK(outcome_since(before, state).result == PollResult::no_reading);
  CHECK(status_word(PollResult::no_reading) == "no-reading");
}

TEST_CASE("a watch row and its CSV line show a refused poll as refused, without angles") {
  SensorState state = with_reading(3);
  state.reading->angle_x = 2.5;
  const auto now = SteadyClock::now();
  state.reading->taken = now;
  const WatchRow row = snapshot_of(101, state, now, std::nullopt, PollResult::refused);
  CHECK(watch_row(row).find("refused") != std::string::npos);
  const std::string line = csv_line(std::chrono::system_clock::time_point{}, row);
  CHECK(line == "1970-01-01T00:00:00.000Z,101,,,,,refused\n");
}
