// A sensor's samples summed up per interval for its long record (docs/monitoring.md, "The long
// record"): count, and least, mean and greatest of each channel, for each interval of UTC
// (intervals are aligned to multiples of their length since the Unix epoch: at 60 s,
// 12:01:00.000..12:01:59.999). Pure: the owner feeds it samples and writes what it closes to
// the sensor's LongRecord.
//
// An interval closes when a sample of a later interval arrives (add()) or when the owner's
// timer finds it over (close_due()), so a sensor that fell silent still gets its last interval
// written. Only one interval is open at a time; an interval without a sample is never made.
//
// A clock stepped back: a sample older than the open interval (or than where the record
// already ends, `not_before`) is dropped and counted in dropped_behind(), never folded into the
// open interval: a row of the record says "measured in this interval", and a sample of three
// hours ago, or taken under a clock three hours wrong, would make that false. So the intervals
// this gives out start later than each other, always: the record is never reordered. The
// clock's state is kept with each row instead (`unsynchronised`).
//
// Memory: fixed (one open interval). Single-threaded.
#pragma once

#include <chrono>
#include <cstdint>
#include <limits>
#include <optional>

#include "monitoring/interval_record.h"

namespace tiltgate::monitoring {

// One reading of a sensor. A channel without a value is NaN (or any non-finite value): y on a
// single-axis sensor, temperature on most, every channel while the sensor has no fresh reading.
struct Sample {
  std::int64_t unix_ms = 0;  // the wall clock when it was taken
  double x = std::numeric_limits<double>::quiet_NaN();
  double y = std::numeric_limits<double>::quiet_NaN();
  double tilt = std::numeric_limits<double>::quiet_NaN();
  double temperature = std::numeric_limits<double>::quiet_NaN();
  // True only when the clock is known to be synchronised (NTP): false by default, so a caller
  // that never says is seen in every row rather than trusted.
  bool clock_synchronised = false;
};

class IntervalSummary {
 public:
  // `interval`: the record's interval, 1 ms .. 49 days (clamped: the record keeps it in 32 bits).
  // `not_before`: where the record on disk already ends (LongRecord::written_until()), so that
  // after a restart a clock behind the record drops samples here, counted, rather than have the
  // record refuse whole intervals.
  explicit IntervalSummary(std::chrono::milliseconds interval,
                           std::optional<std::int64_t> not_before = std::nullopt);

  // Feeds one sample. Returns the interval it closed: the open one, when `sample` belongs to a
  // later interval.
  std::optional<IntervalRecord> add(const Sample& sample);
  // The open interval, closed when `now_unix_ms` is at or past its end; none otherwise (a clock
  // stepped back leaves it open until the clock passes its end again).
  std::optional<IntervalRecord> close_due(std::int64_t now_unix_ms);
  // The open interval, closed now whatever the time: for a clean stop, so its samples are kept
  // (a short interval: its later samples, after a restart, are dropped as behind).
  std::optional<IntervalRecord> close_now();

  std::chrono::milliseconds interval() const { return std::chrono::milliseconds(length_ms_); }
  // The open interval's start, none while none is open.
  std::optional<std::int64_t> open_start() const;
  // Samples dropped since construction because their interval starts before the open one or
  // before `not_before` (a clock stepped back).
  std::uint64_t dropped_behind() const { return dropped_behind_; }

 private:
  struct Channel {
    double min = 0;
    double max = 0;
    double sum = 0;
    std::uint32_t count = 0;

    void add(double value);
    ChannelStats stats() const;
  };

  void open(std::int64_t start);
  IntervalRecord close();

  std::int64_t length_ms_ = 0;
  // Samples before this are dropped: the end of the last interval closed (or `not_before`).
  std::optional<std::int64_t> not_before_;
  bool open_ = false;
  std::int64_t start_ = 0;
  std::uint32_t samples_ = 0;
  std::uint32_t unsynchronised_ = 0;
  Channel x_;
  Channel y_;
  Channel tilt_;
  Channel temperature_;
  std::uint64_t dropped_behind_ = 0;
};

// The start of the interval of length `length_ms` (> 0) that holds `unix_ms`: the greatest
// multiple of the length not after it (before 1970 too).
std::int64_t interval_start(std::int64_t unix_ms, std::int64_t length_ms);

}  // namespace tiltgate::monitoring
