#include "monitoring/burst_recorder.h"

#include <fmt/format.h>

#include <cmath>

namespace tiltgate::monitoring {

BurstRecorder::BurstRecorder(const SensorConfig& sensor)
    : burst_(sensor.burst), pre_trigger_(sensor.pre_trigger), rate_deg_s_(sensor.burst_rate_deg_s) {}

std::optional<std::string> BurstRecorder::trigger_at(
    const FedSample& sample, const std::vector<FedTransition>& transitions) const {
  // An alarm that set at this very reading.
  for (const FedTransition& t : transitions)
    if (t.change.set && t.change.taken == sample.taken)
      return fmt::format("alarm {} {}", to_string(t.change.kind), to_string(t.change.level));
  if (!rate_deg_s_ || !last_ || sample.taken <= last_->taken) return std::nullopt;
  const double seconds = std::chrono::duration<double>(sample.taken - last_->taken).count();
  double fastest = 0;
  for (const auto& [now, before] : {std::pair{sample.x, last_->x}, std::pair{sample.y, last_->y}})
    if (!std::isnan(now) && !std::isnan(before))
      fastest = std::max(fastest, std::fabs(now - before) / seconds);
  if (fastest > *rate_deg_s_) return fmt::format("rate {:.3g} deg/s", fastest);
  return std::nullopt;
}

BurstWork BurstRecorder::take(const std::vector<FedSample>& samples,
                              const std::vector<FedTransition>& transitions) {
  BurstWork work;
  if (burst_.count() == 0) return work;
  for (const FedSample& sample : samples) {
    if (until_) {
      work.samples.push_back(sample);
      if (sample.taken >= *until_) {
        until_.reset();
        work.ended = true;
        // One burst a batch: what follows its end waits for the next batch (a few ms).
      }
    } else if (!work.ended && !work.started) {
      if (auto trigger = trigger_at(sample, transitions)) {
        BurstStart start{*trigger, sample.unix_ms, sample.taken + burst_, {}};
        // The samples within pre_trigger_s before it (the ring may hold one more, just older).
        for (const FedSample& before : recent_)
          if (sample.taken - before.taken <= pre_trigger_) start.pre.push_back(before);
        until_ = start.until;
        work.started = std::move(start);
        work.samples.push_back(sample);
      }
    }
    recent_.push_back(sample);
    while (!recent_.empty() && sample.taken - recent_.front().taken > pre_trigger_)
      recent_.pop_front();
    last_ = sample;
  }
  return work;
}

}  // namespace tiltgate::monitoring
