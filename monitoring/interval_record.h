// One closed interval of a sensor's long record (docs/monitoring.md, "The long record"): how
// many samples it had and the least, mean and greatest value of each channel over them. What
// IntervalSummary makes, LongRecord keeps on disk and history_csv formats. Pure.
#pragma once

#include <cstdint>
#include <limits>

namespace tiltgate::monitoring {

// NaN stands for "no value": a channel the sensor does not have (y on a single-axis sensor,
// temperature on most) or had no sample of in the interval.
inline constexpr float kNoValue = std::numeric_limits<float>::quiet_NaN();

// One channel over one interval. float: the record keeps 4 bytes a value, and 7 significant
// digits are ample for degrees and degrees Celsius.
struct ChannelStats {
  float min = kNoValue;
  float mean = kNoValue;
  float max = kNoValue;
};

struct IntervalRecord {
  // The interval's first millisecond (Unix ms, UTC), a multiple of its length: 12:01:00.000
  // for 12:01:00.000..12:01:59.999.
  std::int64_t start_unix_ms = 0;
  std::uint32_t length_ms = 0;
  std::uint32_t samples = 0;         // every sample fed in the interval, with values or not
  std::uint32_t unsynchronised = 0;  // of them, taken while the clock was not synchronised
  ChannelStats x;
  ChannelStats y;
  ChannelStats tilt;
  ChannelStats temperature;

  // Where the next interval may start: records never overlap.
  std::int64_t end_unix_ms() const { return start_unix_ms + length_ms; }
};

}  // namespace tiltgate::monitoring
