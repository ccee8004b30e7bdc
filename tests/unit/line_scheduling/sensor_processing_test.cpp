// Mounting correction, tilt and alarms of line_scheduling/sensor_processing, on hand-made readings.
#include <doctest/doctest.h>

#include <chrono>
#include <cmath>

#include "line_scheduling/sensor_processing.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

const SteadyClock::time_point t0 = SteadyClock::time_point() + 1h;

Reading reading(double x, double y = NAN, SteadyClock::duration at = 0ms) {
  Reading r;
  r.angle_x = x;
  r.angle_y = y;
  r.taken = t0 + at;
  return r;
}

DerivedState mounted(MountingConfig mounting, double x, double y = NAN) {
  SensorProcessing processing(mounting, AlarmConfig{});
  processing.update(reading(x, y));
  return processing.derived();
}

MountingConfig rotated(double degrees) {
  MountingConfig mounting;
  mounting.rotate_deg = degrees;
  return mounting;
}

// Feeds x values one per 100 ms and returns the alarm flags after each.
std::vector<std::uint16_t> alarms_over(const AlarmConfig& alarms, std::vector<double> xs) {
  SensorProcessing processing(MountingConfig{}, alarms);
  std::vector<std::uint16_t> flags;
  for (std::size_t i = 0; i < xs.size(); ++i) {
    processing.update(reading(xs[i], 0.0, 100ms * int(i)));
    flags.push_back(processing.derived().alarms);
  }
  return flags;
}

}  // namespace

TEST_CASE("before the first reading nothing is valid, and an unmounted reading passes through") {
  SensorProcessing processing(MountingConfig{}, AlarmConfig{});
  CHECK_FALSE(processing.derived().valid);
  CHECK(std::isnan(processing.derived().angle_x));
  processing.update(reading(3.0, -4.0));
  const DerivedState& d = processing.derived();
  CHECK(d.valid);
  CHECK(d.angle_x == 3.0);
  CHECK(d.angle_y == -4.0);
  CHECK(d.tilt == doctest::Approx(4.994169393).epsilon(1e-9));  // exact; hypot says 5
  CHECK(d.alarms == 0);
}

TEST_CASE("swap, then invert, then rotate") {
  MountingConfig swap;
  swap.swap_axes = true;
  CHECK(mounted(swap, 1.0, 2.0).angle_x == 2.0);
  CHECK(mounted(swap, 1.0, 2.0).angle_y == 1.0);

  MountingConfig invert;
  invert.invert_x = true;
  CHECK(mounted(invert, 1.0, 2.0).angle_x == -1.0);
  CHECK(mounted(invert, 1.0, 2.0).angle_y == 2.0);
  invert.invert_y = true;
  CHECK(mounted(invert, 1.0, 2.0).angle_y == -2.0);

  // Swap first, then invert X: X is the sensor's Y, negated.
  MountingConfig both;
  both.swap_axes = true;
  both.invert_x = true;
  CHECK(mounted(both, 1.0, 2.0).angle_x == -2.0);
  CHECK(mounted(both, 1.0, 2.0).angle_y == 1.0);

  // Invert before rotating: (1, 2) -> (-1, 2) -> turned 90: (2, 1).
  MountingConfig invert_then_turn = rotated(90);
  invert_then_turn.invert_x = true;
  CHECK(mounted(invert_then_turn, 1.0, 2.0).angle_x == 2.0);
  CHECK(mounted(invert_then_turn, 1.0, 2.0).angle_y == 1.0);
}

TEST_CASE("quarter turns only swap and negate, exactly") {
  // The frame turned counter-clockwise by 90: the new X is the old Y, the new Y the old -X.
  CHECK(mounted(rotated(90), 1.0, 2.0).angle_x == 2.0);
  CHECK(mounted(rotated(90), 1.0, 2.0).angle_y == -1.0);
  CHECK(mounted(rotated(-90), 1.0, 2.0).angle_x == -2.0);
  CHECK(mounted(rotated(-90), 1.0, 2.0).angle_y == 1.0);
  CHECK(mounted(rotated(270), 1.0, 2.0).angle_x == -2.0);
  CHECK(mounted(rotated(180), 1.0, 2.0).angle_x == -1.0);
  CHECK(mounted(rotated(180), 1.0, 2.0).angle_y == -2.0);
  CHECK(mounted(rotated(-360), 1.0, 2.0).angle_x == 1.0);
  CHECK(mounted(rotated(450), 1.0, 2.0).angle_x == 2.0);
}

TEST_CASE("an askew sensor: the tilt vector is turned into the machine frame, tilt unchanged") {
  // Turned by 30 degrees: x' = x cos 30 + y sin 30, y' = -x sin 30 + y cos 30.
  const DerivedState d = mounted(rotated(30), 10.0, 0.0);
  CHECK(d.angle_x == doctest::Approx(8.660254037844386).epsilon(1e-12));
  CHECK(d.angle_y == doctest::Approx(-5.0).epsilon(1e-12));
  CHECK(d.tilt == doctest::Approx(10.0).epsilon(1e-12));
  const DerivedState diagonal = mounted(rotated(45), 10.0, 10.0);
  CHECK(diagonal.angle_x == doctest::Approx(14.142135623730951).epsilon(1e-12));
  CHECK(diagonal.angle_y == doctest::Approx(0.0).epsilon(1e-12));
}

TEST_CASE("tilt is exact at large angles, whatever the mounting, and tilt alarms use it") {
  // tan^2(tilt) = tan^2(45) + tan^2(45) = 2: 54.7356 degrees, where hypot says 63.64.
  constexpr double exact = 54.735610317245346;
  MountingConfig askew = rotated(30);
  askew.swap_axes = true;
  askew.invert_y = true;
  for (const MountingConfig& mounting : {MountingConfig{}, rotated(30), askew, rotated(-135)}) {
    CHECK(mounted(mounting, 45.0, 45.0).tilt == doctest::Approx(exact).epsilon(1e-9));
    CHECK(mounted(mounting, 150.0, -170.0).tilt ==
          doctest::Approx(mounted(MountingConfig{}, 150.0, -170.0).tilt).epsilon(1e-12));
  }
  CHECK(mounted(MountingConfig{}, 180.0, 180.0).tilt == doctest::Approx(180.0));

  AlarmConfig alarms;
  alarms.tilt_high = 60.0;
  SensorProcessing processing(MountingConfig{}, alarms);
  processing.update(reading(45.0, 45.0));
  CHECK(processing.derived().alarms == 0);  // 54.7 is below 60
  processing.update(reading(50.0, 50.0));   // 59.3: still below
  CHECK(processing.derived().alarms == 0);
  processing.update(reading(55.0, 50.0));   // 61.7
  CHECK(processing.derived().alarms == alarm_bit::tilt_high);
}

TEST_CASE("single-axis sensors: invert_x applies, swap and rotate do not, tilt is |x|") {
  MountingConfig all;
  all.swap_axes = true;
  all.invert_x = true;
  all.invert_y = true;
  all.rotate_deg = 30;
  const DerivedState d = mounted(all, 12.5);
  CHECK(d.angle_x == -12.5);
  CHECK(std::isnan(d.angle_y));
  CHECK(d.tilt == 12.5);
}

TEST_CASE("a high alarm sets above its threshold and clears only below it minus hysteresis") {
  AlarmConfig alarms;
  alarms.x_high = 5.0;
  alarms.hysteresis_deg = 0.5;
  const auto flags = alarms_over(alarms, {4.0, 5.0, 5.01, 4.6, 4.5, 4.49, 5.0});
  using alarm_bit::x_high;
  // 5.0 is not above 5.0; 4.6 and 4.5 are inside the hysteresis band; 4.49 clears.
  CHECK(flags == std::vector<std::uint16_t>{0, 0, x_high, x_high, x_high, 0, 0});
}

TEST_CASE("a low alarm is the mirror image") {
  AlarmConfig alarms;
  alarms.y_low = -3.0;
  alarms.hysteresis_deg = 1.0;
  SensorProcessing processing(MountingConfig{}, alarms);
  std::vector<std::uint16_t> flags;
  for (double y : {-2.0, -3.5, -2.5, -2.0, -1.9}) {
    processing.update(reading(0.0, y));
    flags.push_back(processing.derived().alarms);
  }
  using alarm_bit::y_low;
  CHECK(flags == std::vector<std::uint16_t>{0, y_low, y_low, y_low, 0});
}

TEST_CASE("each threshold has its own bit, checked after mounting") {
  AlarmConfig alarms;
  alarms.x_high = 1.0;
  alarms.x_low = -1.0;
  alarms.y_high = 1.0;
  alarms.y_low = -1.0;
  alarms.tilt_high = 2.5;
  MountingConfig invert;
  invert.invert_x = true;
  SensorProcessing processing(invert, alarms);
  processing.update(reading(2.0, 2.0));  // after mounting: (-2, 2), tilt 2.83
  CHECK(processing.derived().alarms ==
        (alarm_bit::x_low | alarm_bit::y_high | alarm_bit::tilt_high));
  processing.update(reading(-2.0, -2.0));  // (2, -2): lows and highs swap, tilt stays
  CHECK(processing.derived().alarms ==
        (alarm_bit::x_high | alarm_bit::y_low | alarm_bit::tilt_high));
}

TEST_CASE("NaN never sets an alarm and does not clear one that is up") {
  AlarmConfig alarms;
  alarms.x_high = 5.0;
  alarms.y_high = 5.0;
  alarms.tilt_high = 5.0;
  SensorProcessing processing(MountingConfig{}, alarms);
  processing.update(reading(NAN, NAN));
  CHECK(processing.derived().alarms == 0);
  CHECK(std::isnan(processing.derived().tilt));
  processing.update(reading(9.0, 0.0));
  CHECK(processing.derived().alarms == (alarm_bit::x_high | alarm_bit::tilt_high));
  processing.update(reading(NAN, NAN));
  CHECK(processing.derived().alarms == (alarm_bit::x_high | alarm_bit::tilt_high));
  // A single-axis sensor's NaN Y never raises the Y alarm.
  processing.update(reading(0.0));
  CHECK(processing.derived().alarms == 0);
}

TEST_CASE("the rate alarm sets above the limit and clears after a sample within it") {
  AlarmConfig alarms;
  alarms.rate_limit_deg_s = 10.0;
  // 100 ms apart: 0.5 degrees is 5 deg/s, 1.5 degrees is 15 deg/s, 1.0 is exactly the limit.
  const auto flags = alarms_over(alarms, {0.0, 0.5, 2.0, 3.0, 3.5, 5.0});
  using alarm_bit::rate;
  CHECK(flags == std::vector<std::uint16_t>{0, 0, rate, 0, 0, rate});
}

TEST_CASE("the rate counts either axis, uses the readings' own times, and skips NaN") {
  AlarmConfig alarms;
  alarms.rate_limit_deg_s = 1.0;
  SensorProcessing processing(MountingConfig{}, alarms);
  processing.update(reading(0.0, 0.0, 0s));
  processing.update(reading(0.0, 1.5, 1s));  // Y moved 1.5 deg in 1 s
  CHECK(processing.derived().alarms == alarm_bit::rate);
  processing.update(reading(0.0, 3.0, 3s));  // 1.5 deg in 2 s: within
  CHECK(processing.derived().alarms == 0);
  processing.update(reading(NAN, NAN, 4s));
  CHECK(processing.derived().alarms == 0);
  processing.update(reading(50.0, 50.0, 5s));  // no rate across a NaN reading
  CHECK(processing.derived().alarms == 0);
  processing.update(reading(60.0, 50.0, 5s));  // no time passed: no rate either
  CHECK(processing.derived().alarms == 0);
  processing.update(reading(70.0, 50.0, 6s));
  CHECK(processing.derived().alarms == alarm_bit::rate);
}

TEST_CASE("no thresholds configured: no alarms, however far the sensor tilts") {
  const auto flags = alarms_over(AlarmConfig{}, {0.0, 80.0, -80.0, 89.0});
  CHECK(flags == std::vector<std::uint16_t>{0, 0, 0, 0});
}

TEST_CASE("readings relative to the baseline, and the displacement at lever_m") {
  AlarmConfig alarms;
  alarms.displacement_high_mm = 50.0;
  SensorProcessing processing(MountingConfig{}, alarms, 10.0, Baseline{1.0, -0.5});
  processing.update(reading(1.25, -0.5), 1796638502250, true);
  const DerivedState& d = processing.derived();
  CHECK(d.relative_x == doctest::Approx(0.25));
  CHECK(d.relative_y == doctest::Approx(0.0));
  // 1000 x 10 m x (sin 1.25 deg - sin 1 deg) = 43.62 mm (docs/monitoring.md's formula).
  const double expected = 10000.0 * (std::sin(1.25 * M_PI / 180) - std::sin(1.0 * M_PI / 180));
  CHECK(d.displacement_x_mm == doctest::Approx(expected));
  CHECK(d.displacement_x_mm == doctest::Approx(43.62).epsilon(0.001));
  CHECK(d.displacement_y_mm == doctest::Approx(0.0));
  CHECK(d.displacement_mm == doctest::Approx(expected));
  CHECK(d.alarms == 0);
  CHECK(d.taken_unix_ms == 1796638502250);
  CHECK(d.clock_synchronised);
  // A new baseline applies at once to what is served.
  processing.set_baseline(Baseline{0.0, 0.0});
  CHECK(processing.derived().relative_x == doctest::Approx(1.25));
  CHECK(processing.derived().displacement_mm > 50.0);
  processing.update(reading(1.25, -0.5, 100ms), 1796638502350, false);
  CHECK(processing.derived().alarms == alarm_bit::displacement);
  CHECK_FALSE(processing.derived().clock_synchronised);
  REQUIRE(processing.changed().size() == 1);
  CHECK(processing.changed()[0].kind == AlarmKind::displacement_high);
  processing.update(reading(1.25, -0.5, 200ms));
  CHECK(processing.changed().empty());  // only the reading's own changes
}

TEST_CASE("without lever_m there is no displacement, and one axis has no Y") {
  SensorProcessing processing(MountingConfig{}, AlarmConfig{}, std::nullopt, Baseline{2.0, 0.0});
  processing.update(reading(-1.0));
  CHECK(processing.derived().relative_x == doctest::Approx(-3.0));
  CHECK(std::isnan(processing.derived().relative_y));
  CHECK(std::isnan(processing.derived().displacement_mm));
  SensorProcessing lever(MountingConfig{}, AlarmConfig{}, 2.0, Baseline{});
  lever.update(reading(-1.0));
  CHECK(lever.derived().displacement_mm == doctest::Approx(2000.0 * std::sin(M_PI / 180)));
  CHECK(std::isnan(lever.derived().displacement_y_mm));
}
