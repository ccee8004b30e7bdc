#include "monitoring/interval_merge.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "monitoring/interval_summary.h"

namespace tiltgate::monitoring {

namespace {

float merged_min(float a, float b) { return std::isnan(a) ? b : std::isnan(b) ? a : std::min(a, b); }
float merged_max(float a, float b) { return std::isnan(a) ? b : std::isnan(b) ? a : std::max(a, b); }

// The mean of two intervals' means, weighted by their samples. The record keeps one count for
// every channel, so a channel that had no value in some samples is weighted a little off; the
// least and greatest are exact.
float merged_mean(float a, std::uint32_t a_samples, float b, std::uint32_t b_samples) {
  if (std::isnan(a)) return b;
  if (std::isnan(b)) return a;
  const double weight = static_cast<double>(a_samples) + b_samples;
  if (weight == 0) return a;
  return static_cast<float>((static_cast<double>(a) * a_samples + static_cast<double>(b) * b_samples) /
                            weight);
}

void merge_channel(ChannelStats& into, std::uint32_t into_samples, const ChannelStats& from,
                   std::uint32_t from_samples) {
  into.min = merged_min(into.min, from.min);
  into.mean = merged_mean(into.mean, into_samples, from.mean, from_samples);
  into.max = merged_max(into.max, from.max);
}

}  // namespace

IntervalMerge::IntervalMerge(std::int64_t step_ms) : step_ms_(std::max<std::int64_t>(step_ms, 1)) {}

std::optional<IntervalRecord> IntervalMerge::add(const IntervalRecord& interval) {
  const std::int64_t step = interval_start(interval.start_unix_ms, step_ms_);
  if (open_ && step < open_->start_unix_ms) return std::nullopt;
  std::optional<IntervalRecord> closed;
  if (open_ && step != open_->start_unix_ms) closed = finish();
  if (!open_) {
    open_ = interval;
    open_->start_unix_ms = step;
    open_->length_ms = static_cast<std::uint32_t>(
        std::min<std::int64_t>(step_ms_, std::numeric_limits<std::uint32_t>::max()));
    return closed;
  }
  IntervalRecord& into = *open_;
  merge_channel(into.x, into.samples, interval.x, interval.samples);
  merge_channel(into.y, into.samples, interval.y, interval.samples);
  merge_channel(into.tilt, into.samples, interval.tilt, interval.samples);
  merge_channel(into.temperature, into.samples, interval.temperature, interval.samples);
  into.samples += interval.samples;
  into.unsynchronised += interval.unsynchronised;
  return closed;
}

std::optional<IntervalRecord> IntervalMerge::finish() {
  std::optional<IntervalRecord> closed;
  closed.swap(open_);
  return closed;
}

std::int64_t graph_step_ms(std::int64_t range_ms, std::int64_t max_points,
                           std::int64_t record_interval_ms) {
  constexpr std::int64_t kMinuteMs = 60'000;
  constexpr std::array<std::int64_t, 9> kSteps = {
      kMinuteMs,           5 * kMinuteMs,       15 * kMinuteMs,
      30 * kMinuteMs,      60 * kMinuteMs,      3 * 60 * kMinuteMs,
      6 * 60 * kMinuteMs,  12 * 60 * kMinuteMs, 24 * 60 * kMinuteMs};
  max_points = std::max<std::int64_t>(max_points, 1);
  record_interval_ms = std::max<std::int64_t>(record_interval_ms, 1);
  const auto fits = [&](std::int64_t step) { return (range_ms + step - 1) / step <= max_points; };
  if (fits(record_interval_ms)) return record_interval_ms;
  for (const std::int64_t step : kSteps)
    if (step > record_interval_ms && fits(step)) return step;
  const std::int64_t day = kSteps.back();
  const std::int64_t days = (range_ms + day * max_points - 1) / (day * max_points);
  return std::max<std::int64_t>(days, 1) * day;
}

}  // namespace tiltgate::monitoring
