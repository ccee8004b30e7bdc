#include "monitoring/interval_summary.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tiltgate::monitoring {

std::int64_t interval_start(std::int64_t unix_ms, std::int64_t length_ms) {
  // Floor division: C++'s / truncates toward zero, which would put 1969's times one interval
  // late.
  std::int64_t quotient = unix_ms / length_ms;
  if (unix_ms % length_ms != 0 && unix_ms < 0) --quotient;
  return quotient * length_ms;
}

void IntervalSummary::Channel::add(double value) {
  if (!std::isfinite(value)) return;
  min = count == 0 ? value : std::min(min, value);
  max = count == 0 ? value : std::max(max, value);
  sum += value;
  ++count;
}

ChannelStats IntervalSummary::Channel::stats() const {
  if (count == 0) return {};
  return {static_cast<float>(min), static_cast<float>(sum / count), static_cast<float>(max)};
}

IntervalSummary::IntervalSummary(std::chrono::milliseconds interval,
                                 std::optional<std::int64_t> not_before)
    : length_ms_(std::clamp<std::int64_t>(interval.count(), 1,
                                          std::numeric_limits<std::uint32_t>::max())),
      not_before_(not_before) {}

std::optional<std::int64_t> IntervalSummary::open_start() const {
  if (!open_) return std::nullopt;
  return start_;
}

std::optional<IntervalRecord> IntervalSummary::add(const Sample& sample) {
  const std::int64_t start = interval_start(sample.unix_ms, length_ms_);
  // An interval that starts before `not_before` would overlap what is written (the interval's
  // length changed since): its samples are dropped too.
  const bool behind = (open_ && start < start_) || (not_before_ && start < *not_before_);
  if (behind) {
    ++dropped_behind_;
    return std::nullopt;
  }
  std::optional<IntervalRecord> closed;
  if (open_ && start != start_) closed = close();
  if (!open_) open(start);
  ++samples_;
  if (!sample.clock_synchronised) ++unsynchronised_;
  x_.add(sample.x);
  y_.add(sample.y);
  tilt_.add(sample.tilt);
  temperature_.add(sample.temperature);
  return closed;
}

std::optional<IntervalRecord> IntervalSummary::close_due(std::int64_t now_unix_ms) {
  if (!open_ || now_unix_ms < start_ + length_ms_) return std::nullopt;
  return close();
}

std::optional<IntervalRecord> IntervalSummary::close_now() {
  if (!open_) return std::nullopt;
  return close();
}

void IntervalSummary::open(std::int64_t start) {
  open_ = true;
  start_ = start;
  samples_ = 0;
  unsynchronised_ = 0;
  x_ = y_ = tilt_ = temperature_ = Channel{};
}

IntervalRecord IntervalSummary::close() {
  IntervalRecord record;
  record.start_unix_ms = start_;
  record.length_ms = static_cast<std::uint32_t>(length_ms_);
  record.samples = samples_;
  record.unsynchronised = unsynchronised_;
  record.x = x_.stats();
  record.y = y_.stats();
  record.tilt = tilt_.stats();
  record.temperature = temperature_.stats();
  open_ = false;
  // Whatever comes now belongs to a later interval: an interval is given out once.
  not_before_ = start_ + length_ms_;
  return record;
}

}  // namespace tiltgate::monitoring
