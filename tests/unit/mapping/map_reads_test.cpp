// What configured points read: scaled integers, angle units, corrected angles and alarms from
// the derived state, bits, the offline policies, and writes through scaled and reordered
// points.
#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "mapping/default_maps.h"
#include "mapping/map_access.h"
#include "mapping/tilt.h"
#include "mapping/value_codec.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using Words = std::vector<std::uint16_t>;

SensorState sensor_at(SteadyClock::time_point now, double x, double y) {
  SensorState s;
  s.online = true;
  s.identity_known = true;
  s.counters.polls_ok = 5;
  Reading r;
  r.angle_x = x;
  r.angle_y = y;
  r.taken = now - 10ms;
  s.reading = r;
  return s;
}

Point input(std::string name, std::uint16_t address, PointType type, ValueSource source) {
  return make_point(std::move(name), RegisterTable::input, address, type, source);
}

Words read(const RegisterMap& map, const SensorView& view, std::uint16_t address,
           std::uint16_t count) {
  auto words = read_registers(map, view, RegisterTable::input, address, count);
  REQUIRE(words.has_value());
  return *words;
}

}  // namespace

TEST_CASE("an angle as int16 hundredths through scale 100, and negative values") {
  Point p = input("x", 0, PointType::int16, ValueSource::angle_x);
  p.scale = 100;
  const RegisterMap map({p});
  const auto now = SteadyClock::now();
  const auto state = sensor_at(now, -12.345, 0);
  const SensorView view{state, now, 1000ms, {}};
  CHECK(std::int16_t(read(map, view, 0, 1)[0]) == -1235);  // -1234.5 rounds away from zero
}

TEST_CASE("offset and negative scale apply before rounding and saturation") {
  Point p = input("x", 0, PointType::uint16, ValueSource::angle_x);
  p.scale = -10;
  p.offset = 1000;
  p.rounding = Rounding::floor;
  const RegisterMap map({p});
  const auto now = SteadyClock::now();
  auto state = sensor_at(now, 2.55, 0);
  CHECK(read(map, SensorView{state, now, 1000ms, {}}, 0, 1)[0] == 974);  // 974.5 floored
  state.reading->angle_x = 170;                                          // -700: below 0
  CHECK(read(map, SensorView{state, now, 1000ms, {}}, 0, 1)[0] == 0);
}

TEST_CASE("angles in milliradians and percent grade") {
  Point mrad = input("mrad", 0, PointType::float32, ValueSource::angle_x);
  mrad.angle_unit = AngleUnit::milliradians;
  Point grade = input("grade", 2, PointType::float64, ValueSource::angle_y);
  grade.angle_unit = AngleUnit::percent_grade;
  const RegisterMap map({mrad, grade});
  const auto now = SteadyClock::now();
  const auto state = sensor_at(now, 45.0, 45.0);
  const SensorView view{state, now, 1000ms, {}};
  const Words w = read(map, view, 0, 6);
  CHECK(decode_number(std::span(w).first(2), PointType::float32, RegisterOrder::abcd) ==
        doctest::Approx(std::numbers::pi / 4 * 1000).epsilon(1e-6));
  CHECK(decode_number(std::span(w).subspan(2, 4), PointType::float64, RegisterOrder::abcd) ==
        doctest::Approx(100.0));
}

TEST_CASE("angles, tilt and alarms come from the derived state once it is valid") {
  const RegisterMap map = default_map(registered_families(), "h6");
  const auto now = SteadyClock::now();
  const auto state = sensor_at(now, 3.0, 4.0);
  SensorView raw{state, now, 1000ms, {}};
  Words w = read(map, raw, 25, 3);
  // The exact tilt of the raw reading (mapping/tilt.h), not hypot(3, 4) = 5.
  CHECK(get_float32(std::span(w).first<2>(), WordOrder::big) == float(tilt_degrees(3.0, 4.0)));
  CHECK(get_float32(std::span(w).first<2>(), WordOrder::big) ==
        doctest::Approx(4.994169393).epsilon(1e-7));
  CHECK(w[2] == 0);

  DerivedState derived;
  derived.angle_x = -4.0;
  derived.angle_y = 3.0;
  derived.tilt = 5.0;
  derived.alarms = alarm_bit::x_low | alarm_bit::rate;
  derived.valid = true;
  SensorView corrected{state, now, 1000ms, {}, WordOrder::big, &derived};
  w = read(map, corrected, 0, 8);
  CHECK(get_float32(std::span(w).first<2>(), WordOrder::big) == -4.0f);
  CHECK(std::int16_t(w[4]) == -400);
  CHECK(std::int16_t(w[5]) == 300);
  CHECK(w[6] == (status_bit::online | status_bit::alarm_active));
  CHECK(read(map, corrected, 27, 1)[0] == (alarm_bit::x_low | alarm_bit::rate));
  auto bits = read_bits(map, corrected, RegisterTable::discrete, 0, 7);
  REQUIRE(bits.has_value());
  CHECK(*bits == std::vector<bool>{true, false, true, false, false, false, true});
}

TEST_CASE("a single-axis sensor's tilt is |x|") {
  const RegisterMap map = default_map(registered_families(), "h4360");
  const auto now = SteadyClock::now();
  const auto state = sensor_at(now, -30.5, NAN);
  const Words w = read(map, SensorView{state, now, 1000ms, {}}, 25, 2);
  CHECK(get_float32(std::span(w).first<2>(), WordOrder::big) == 30.5f);
}

TEST_CASE("bit points pick one status bit, and a packed register carries several") {
  Point stale = input("stale", 0, PointType::boolean, ValueSource::status);
  stale.table = RegisterTable::discrete;
  stale.bit = 1;
  Point packed = input("flags", 0, PointType::uint16, ValueSource::bits);
  packed.bits = {ValueSource::online, std::nullopt, ValueSource::stale, ValueSource::alarm_tilt};
  const RegisterMap map({stale, packed});
  const auto now = SteadyClock::now();
  auto state = sensor_at(now, 1, 1);
  state.last_answer = now + 4900ms;  // it answers (a refusal to each poll), its reading ages
  DerivedState derived;
  derived.alarms = alarm_bit::tilt_high;
  derived.valid = true;
  const SensorView view{state, now + 5s, 1000ms, {}, WordOrder::big, &derived};
  CHECK(read(map, view, 0, 1)[0] == 0b1101);
  auto bits = read_bits(map, view, RegisterTable::discrete, 0, 1);
  REQUIRE(bits.has_value());
  CHECK((*bits)[0] == true);
}

TEST_CASE("offline reads: exception, last value or a substitute") {
  const RegisterMap map = default_map(registered_families(), "h6");
  const auto now = SteadyClock::now();
  auto state = sensor_at(now, 1.5, -2.25);
  state.online = false;
  SensorView view{state, now, 1000ms, {}};
  CHECK(read_registers(map, view, RegisterTable::input, 0, 6).error() == MapFault::unavailable);

  view.offline = OfflineRead::last_value;
  Words w = read(map, view, 0, 6);
  CHECK(get_float32(std::span(w).first<2>(), WordOrder::big) == 1.5f);
  CHECK(std::int16_t(w[5]) == -225);

  view.offline = OfflineRead::substitute;
  view.substitute = -999;
  w = read(map, view, 0, 7);
  CHECK(get_float32(std::span(w).first<2>(), WordOrder::big) == -999.0f);
  CHECK(std::int16_t(w[4]) == -999);  // shown as is, not scaled to hundredths
  CHECK(w[6] == 0);                   // status is no measurement: offline, not stale
}

TEST_CASE("offline last value is still an exception before the first reading") {
  const RegisterMap map = default_map(registered_families(), "h6");
  SensorState never;
  SensorView view{never, SteadyClock::now(), 1000ms, {}};
  view.offline = OfflineRead::last_value;
  CHECK(read_registers(map, view, RegisterTable::input, 0, 2).error() == MapFault::unavailable);
  CHECK(read_registers(map, view, RegisterTable::input, 6, 1).has_value());
}

TEST_CASE("a wrong device answering reads as offline says, with status bit 6 and discrete input 7") {
  const RegisterMap map = default_map(registered_families(), "h6");
  const auto now = SteadyClock::now();
  auto state = sensor_at(now, 1.5, -2.25);  // online, its reading fresh: the configured one's
  state.wrong_device = true;
  SensorView view{state, now, 1000ms, {}};
  CHECK(read_registers(map, view, RegisterTable::input, 0, 2).error() == MapFault::unavailable);
  const Words status = read(map, view, 6, 1);
  CHECK(status[0] == (status_bit::online | status_bit::wrong_device));
  auto bits = read_bits(map, view, RegisterTable::discrete, 7, 1);
  REQUIRE(bits.has_value());
  CHECK((*bits)[0] == true);

  view.offline = OfflineRead::last_value;  // the configured sensor's last reading
  Words w = read(map, view, 0, 2);
  CHECK(get_float32(std::span(w).first<2>(), WordOrder::big) == 1.5f);
  view.offline = OfflineRead::substitute;
  view.substitute = -999;
  w = read(map, view, 0, 2);
  CHECK(get_float32(std::span(w).first<2>(), WordOrder::big) == -999.0f);

  state.wrong_device = false;
  view.offline = OfflineRead::exception;
  CHECK(read_registers(map, view, RegisterTable::input, 0, 2).has_value());
  bits = read_bits(map, view, RegisterTable::discrete, 7, 1);
  REQUIRE(bits.has_value());
  CHECK((*bits)[0] == false);
}

TEST_CASE("the standby of a redundant pair serves what it heard, with status bit 7 and discrete input 8") {
  const RegisterMap map = default_map(registered_families(), "h6");
  const auto now = SteadyClock::now();
  auto state = sensor_at(now, 1.5, -2.25);  // heard on the line: the active gateway's poll
  state.standby = true;
  const SensorView view{state, now, 1000ms, {}};
  // Served as a reading of its own would be: the values are the sensor's, only heard.
  const Words w = read(map, view, 0, 7);
  CHECK(get_float32(std::span(w).first<2>(), WordOrder::big) == 1.5f);
  CHECK(w[6] == (status_bit::online | status_bit::standby));
  CHECK(status_bit::standby == 0x80);
  auto bits = read_bits(map, view, RegisterTable::discrete, 0, 9);
  REQUIRE(bits.has_value());
  CHECK(*bits == std::vector<bool>{true, false, false, false, false, false, false, false, true});
  CHECK(map.find("standby")->table == RegisterTable::discrete);
  CHECK(map.find("standby")->address == 8);

  state.standby = false;  // taken over: active, polling itself
  CHECK(read(map, view, 6, 1)[0] == status_bit::online);
  bits = read_bits(map, view, RegisterTable::discrete, 8, 1);
  REQUIRE(bits.has_value());
  CHECK((*bits)[0] == false);
}

TEST_CASE("a map's status point holds all nine status bits") {
  // A uint16 packing every one-bit status source, and the status word itself, agree.
  Point packed = input("flags", 0, PointType::uint16, ValueSource::bits);
  packed.bits = {ValueSource::online,       ValueSource::stale,        ValueSource::last_write_failed,
                 ValueSource::identity_unknown, ValueSource::alarm_active, ValueSource::answers_late,
                 ValueSource::wrong_device, ValueSource::standby, ValueSource::clock_unsynchronised};
  const RegisterMap map({packed, input("status", 1, PointType::uint16, ValueSource::status)});
  const auto now = SteadyClock::now();
  auto state = sensor_at(now, 1, 1);
  state.wrong_device = true;
  state.standby = true;
  const Words w = read(map, SensorView{state, now, 1000ms, {}}, 0, 2);
  CHECK(w[0] == w[1]);
  CHECK(w[1] == (status_bit::online | status_bit::wrong_device | status_bit::standby));
  CHECK(source_range(ValueSource::status, AngleUnit::degrees).max == 511);
  CHECK(is_bit_source(ValueSource::standby));
  CHECK_FALSE(is_measurement(ValueSource::standby));
}

TEST_CASE("a write through a scaled, word-swapped point is decoded before the range check") {
  Point zero;
  zero.name = "zero_x_cdeg";
  zero.table = RegisterTable::holding;
  zero.address = 10;
  zero.type = PointType::int32;
  zero.order = RegisterOrder::cdab;
  zero.scale = 100;
  zero.write = WriteTarget::zero_x;
  zero.min = -180;
  zero.max = 180;
  const RegisterMap map({zero});
  const Words words{0xE0C0, 0xFFFF};  // -8000 = 0xFFFFE0C0, low word first
  auto plan = plan_register_write(map, WordOrder::big, 10, words);
  REQUIRE(plan.has_value());
  CHECK(plan->front().value == -80.0);
  const Words too_far{0x4E20, 0x0000};  // 20000 -> 200 degrees
  CHECK(plan_register_write(map, WordOrder::big, 10, too_far).error() == MapFault::illegal_value);
}

TEST_CASE("a sensor not heard from for stale_after reads offline, its angles 0x0B, though its poll still runs") {
  // The driver has not finished the poll that finds the sensor silent (its retries and their
  // late-reply guards take longer than stale_after), so state.online still says the last
  // exchange was answered.
  const auto now = SteadyClock::now();
  SensorState state = sensor_at(now, 1.5, -2.25);
  state.last_answer = state.reading->taken - 1ms;  // the Get Angle reply, just before the reading
  const RegisterMap map({input("x", 0, PointType::float32, ValueSource::angle_x),
                         input("status", 2, PointType::uint16, ValueSource::status)});

  const SensorView fresh{state, state.reading->taken + 1000ms, 1000ms, {}};
  CHECK(fresh.online());
  CHECK_FALSE(fresh.stale());
  CHECK((fresh.status() & status_bit::online) != 0);

  const SensorView silent{state, state.reading->taken + 1001ms, 1000ms, {}};
  CHECK_FALSE(silent.online());
  CHECK(silent.stale());
  CHECK((silent.status() & status_bit::online) == 0);
  const auto angles = read_registers(map, silent, RegisterTable::input, 0, 2);
  REQUIRE_FALSE(angles.has_value());
  CHECK(angles.error() == MapFault::unavailable);
  CHECK((read(map, silent, 2, 1)[0] & status_bit::online) == 0);

  // A sensor that answers (a NAK to every measurement) stays online while its reading ages.
  state.last_answer = state.reading->taken + 900ms;
  const SensorView refusing{state, state.reading->taken + 1500ms, 1000ms, {}};
  CHECK(refusing.online());
  CHECK(refusing.stale());
}
