#include "commission/poll_outcome.h"

#include <numeric>

namespace tiltgate {

namespace {

std::uint64_t refusals_counted(const SensorCounters& counters) {
  return std::accumulate(counters.refusals.begin(), counters.refusals.end(), std::uint64_t{0});
}

}  // namespace

PollMark mark_before_poll(const SensorState& state) {
  return {state.reading.has_value(), state.sample_seq, refusals_counted(state.counters),
          state.counters.last_refusal};
}

PollOutcome outcome_since(const PollMark& before, const SensorState& after) {
  if (after.reading && (!before.had_reading || after.sample_seq != before.sample_seq))
    return {PollResult::reading};
  // A refusal is an answer even when a time-out followed it in the same poll (a driver that
  // asks twice): the code is what the user needs.
  const bool refused = after.counters.last_refusal &&
                       (refusals_counted(after.counters) != before.refusals ||
                        after.counters.last_refusal != before.last_refusal);
  if (refused) return {PollResult::refused, *after.counters.last_refusal};
  if (!after.online) return {PollResult::silent};
  return {PollResult::no_reading};
}

}  // namespace tiltgate
