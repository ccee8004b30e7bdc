// Triggered bursts (monitoring/burst_recorder.h): an alarm that sets, or a fast change, starts
// one with the samples of pre_trigger_s before it; it ends burst_s after; a trigger during it is
// part of it; without burst_s nothing starts.
#include <doctest/doctest.h>

#include <chrono>

#include "monitoring/burst_recorder.h"

using namespace tiltgate;
using namespace tiltgate::monitoring;
using namespace std::chrono_literals;

namespace {

const SteadyClock::time_point t0 = SteadyClock::time_point() + 1h;

FedSample sample_at(std::chrono::milliseconds at, double x) {
  FedSample s;
  s.taken = t0 + at;
  s.unix_ms = 1796638500000 + at.count();
  s.x = x;
  return s;
}

FedTransition set_at(const FedSample& s) {
  AlarmTransition t;
  t.kind = AlarmKind::x_high;
  t.level = AlarmLevel::danger;
  t.set = true;
  t.taken = s.taken;
  return {t, s.unix_ms};
}

SensorConfig bursting(std::chrono::seconds burst, std::chrono::seconds pre) {
  SensorConfig c;
  c.burst = burst;
  c.pre_trigger = pre;
  return c;
}

}  // namespace

TEST_CASE("burst: an alarm that sets starts one, with pre_trigger_s of samples before it") {
  BurstRecorder bursts(bursting(2s, 1s));
  std::vector<FedSample> quiet;
  for (int i = 0; i < 20; ++i) quiet.push_back(sample_at(i * 100ms, 1.0));  // 0..1.9 s
  CHECK_FALSE(bursts.take(quiet, {}).started.has_value());
  const FedSample trigger = sample_at(2000ms, 3.0);
  BurstWork work = bursts.take({trigger}, {set_at(trigger)});
  REQUIRE(work.started.has_value());
  CHECK(work.started->trigger == "alarm x_high danger");
  CHECK(work.started->unix_ms == trigger.unix_ms);
  CHECK(work.started->until == trigger.taken + 2s);
  // The samples within 1 s before the trigger: 1.0..1.9 s.
  REQUIRE(work.started->pre.size() == 10);
  CHECK(work.started->pre.front().taken == t0 + 1000ms);
  REQUIRE(work.samples.size() == 1);  // the trigger itself
  CHECK(bursts.running());
  // A trigger during the burst is part of it; the sample at its end ends it.
  const FedSample again = sample_at(3000ms, 5.0);
  work = bursts.take({again, sample_at(3500ms, 5.0)}, {set_at(again)});
  CHECK_FALSE(work.started.has_value());
  CHECK(work.samples.size() == 2);
  CHECK_FALSE(work.ended);
  work = bursts.take({sample_at(4000ms, 5.0), sample_at(4100ms, 5.0)}, {});
  CHECK(work.ended);
  CHECK(work.samples.size() == 1);  // up to its end; what follows is no burst's
  CHECK_FALSE(bursts.running());
}

TEST_CASE("burst: a change faster than burst_rate_deg_s starts one, and without burst_s none does") {
  SensorConfig config = bursting(1s, 0s);
  config.burst_rate_deg_s = 1.0;
  BurstRecorder bursts(config);
  CHECK_FALSE(bursts.take({sample_at(0ms, 1.0), sample_at(100ms, 1.05)}, {}).started);  // 0.5/s
  const BurstWork work = bursts.take({sample_at(200ms, 1.3)}, {});  // 2.5 deg/s
  REQUIRE(work.started.has_value());
  CHECK(work.started->trigger.rfind("rate 2.5", 0) == 0);
  CHECK(work.started->pre.empty());  // pre_trigger_s 0

  BurstRecorder off(bursting(0s, 10s));
  const FedSample s = sample_at(0ms, 9.0);
  CHECK_FALSE(off.take({s}, {set_at(s)}).started.has_value());
}
