// What one poll of a sensor came to, for a commissioning command to tell the user: a reading,
// a refusal (a NAK or an exception, with its code), silence, or an answer that held no reading.
// A refusal is an answer: it is never reported as "no reply". Pure: the caller hands in the
// sensor's state before and after the poll.
#pragma once

#include <cstdint>
#include <optional>

#include "driver/sensor_state.h"

namespace tiltgate {

// The parts of a sensor's state a poll changes, taken before it.
struct PollMark {
  bool had_reading = false;
  std::uint16_t sample_seq = 0;
  std::uint64_t refusals = 0;  // every refusal counted so far
  std::optional<std::uint8_t> last_refusal;
};

PollMark mark_before_poll(const SensorState& state);

enum class PollResult : std::uint8_t {
  reading,     // a new measurement arrived
  refused,     // the sensor answered with a refusal and gave no reading
  silent,      // the last exchange got no valid reply
  no_reading,  // the sensor answered, but nothing it sent was a usable measurement
};

struct PollOutcome {
  PollResult result = PollResult::silent;
  std::uint8_t refusal = 0;  // result refused: the protocol's code
};

PollOutcome outcome_since(const PollMark& before, const SensorState& after);

}  // namespace tiltgate
