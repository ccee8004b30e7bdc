// How the commissioning commands show a sensor: `info`'s lines, `watch`'s table rows and its
// CSV log. Pure: the caller passes the clock's readings in.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "driver/sensor_state.h"
#include "commission/commission_events.h"
#include "commission/poll_outcome.h"

namespace tiltgate {

// One sensor as `watch` shows it at one moment.
struct WatchRow {
  std::uint32_t address = 0;
  std::string serial;                  // empty until the sensor has told it
  std::optional<double> angle_x;       // the last reading's; none before the first
  std::optional<double> angle_y;       // none on single-axis sensors too
  // What the last poll came to; a reading when the row shows one just taken.
  PollResult result = PollResult::silent;
  std::optional<std::chrono::milliseconds> age;  // of the last reading
  std::optional<double> polls_per_second;  // readings per second; none before the second
};

// How often a sensor's readings arrive: readings after the first over the time since it.
class ReadingRate {
 public:
  // Call after each poll: counts the reading if it is a new one.
  void update(const SensorState& state);
  std::optional<double> per_second() const;

 private:
  std::uint16_t last_seq_ = 0;
  bool seen_ = false;
  std::uint64_t readings_ = 0;
  SteadyClock::time_point first_{};
  SteadyClock::time_point last_{};
};

// `outcome`: what the last poll came to (poll_outcome.h); none: as the state says (answering
// or silent), for a state that was not just polled.
WatchRow snapshot_of(std::uint32_t address, const SensorState& state,
                     SteadyClock::time_point now, std::optional<double> polls_per_second,
                     std::optional<PollResult> outcome = std::nullopt);

// The tilt from vertical of a reading's angles (mapping/tilt.h); none without an X angle.
std::optional<double> tilt_of(const WatchRow& snapshot);

// "ok", "no-reply", "refused" (a NAK or an exception: an answer, but no reading) or
// "no-reading": one word, so that plain lines split on blanks.
std::string_view status_word(PollResult result);

// `text`, or "-" when it is empty (an identity the sensor did not report).
std::string or_dash(const std::string& text);

// `watch`'s table: a header and one row per sensor, in fixed-width columns.
std::string watch_header();
std::string watch_row(const WatchRow& snapshot);

// 2026-12-01T20:40:01.123Z
std::string iso8601_utc_ms(std::chrono::system_clock::time_point time);

// `watch --log`: the header, and one line per poll. A poll that got no reading leaves the
// angles empty.
std::string csv_header();
std::string csv_line(std::chrono::system_clock::time_point time, const WatchRow& snapshot);

// What `state` holds of the sensor at `address`, run as `model`, for a SensorReadingEvent: its
// identity, its last reading's angles and age at `now`; the result as the state says
// (answering or silent) and no status words, for the caller to fill in from its poll.
SensorReadingEvent reading_of(std::uint32_t address, std::string_view model,
                              const SensorState& state, SteadyClock::time_point now);

// The event as `watch`'s row.
WatchRow watch_row_of(const SensorReadingEvent& reading);

// `info`: one "name: value" line each for the address, model, serial, firmware, lock level,
// angles and tilt; "-" for what the sensor has not told or its protocol does not have.
std::string sensor_info_text(const SensorReadingEvent& reading);
std::string sensor_info_text(std::uint32_t address, std::string_view model,
                             const SensorState& state);

}  // namespace tiltgate
