// The rendered register image against read_registers(), the reference it must equal: every
// range of every table of a sensor's default map, and of a map with gaps, strings and
// written registers, in every state of the sensor (fresh, stale, offline, never read) under
// every offline policy and word order. Same words, same exception, every time.
#include <doctest/doctest.h>

#include <string>

#include "driver/family.h"
#include "mapping/default_maps.h"
#include "mapping/register_image.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using Words = std::vector<std::uint16_t>;

// A sensor heard from `age` ago, online or not; no reading at all with `read` false.
SensorState sensor(SteadyClock::time_point now, std::chrono::milliseconds age, bool online,
                   bool read = true) {
  SensorState s;
  s.online = online;
  s.identity_known = true;
  s.serial = "SN 4711";
  s.firmware = "1.2";
  s.counters.polls_ok = 70000;
  s.counters.timeouts = 3;
  s.bus_address = 5;
  if (read) {
    Reading r;
    r.angle_x = -12.345;
    r.angle_y = 3.5;
    r.taken = now - age;
    s.reading = r;
  }
  return s;
}

// A map with a gap, a string, a float, an age and a written holding register.
RegisterMap gappy_map() {
  Point x = make_point("x", RegisterTable::input, 0, PointType::int16, ValueSource::angle_x);
  x.scale = 100;
  const Point y = make_point("y", RegisterTable::input, 1, PointType::float32, ValueSource::angle_y);
  const Point age = make_point("age", RegisterTable::input, 5, PointType::uint16, ValueSource::age_ms);
  const Point serial = make_point("serial", RegisterTable::input, 6, PointType::string, ValueSource::serial);
  const Point status = make_point("status", RegisterTable::input, 20, PointType::uint16, ValueSource::status);
  const Point held = make_point("held", RegisterTable::holding, 3, PointType::uint32, ValueSource::written);
  return RegisterMap({x, y, age, serial, status, held});
}

// Every range of `table` from address 0 to a little past the map, up to 12 registers long and
// a long one from each address: the image and read_registers() agree on each.
void check_every_range(const RegisterMap& map, const SensorView& view, RegisterTable table) {
  RegisterImage image;
  for (std::uint32_t address = 0; address < 48; ++address) {
    for (std::uint32_t count : {1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 10u, 11u, 12u, 38u, 125u}) {
      if (address + count > 0x10000) continue;
      Words expected(count, 0xEEEE), got(count, 0xDDDD);
      const auto reference = read_registers(map, view, table, std::uint16_t(address), expected);
      const auto rendered = image.read(map, view, table, std::uint16_t(address), got);
      INFO("address ", address, " count ", count);
      REQUIRE(rendered.has_value() == reference.has_value());
      if (reference) {
        CHECK(got == expected);
      } else {
        CHECK(rendered.error() == reference.error());
      }
    }
  }
}

void check_every_state(const RegisterMap& map) {
  const auto now = SteadyClock::now();
  const std::vector<std::pair<std::string, SensorState>> states = {
      {"fresh", sensor(now, 10ms, true)},
      {"stale but online", sensor(now, 1500ms, true)},
      {"offline", sensor(now, 10ms, false)},
      {"offline and stale", sensor(now, 5s, false)},
      {"never read", sensor(now, 0ms, false, false)},
  };
  const Words written = {0, 0, 0, 0x1234, 0x5678};
  for (const auto& named : states) {  // not a structured binding: clang 14's INFO cannot take one
    const std::string& name = named.first;
    const SensorState& state = named.second;
    for (const OfflineRead policy :
         {OfflineRead::exception, OfflineRead::last_value, OfflineRead::substitute}) {
      for (const WordOrder order : {WordOrder::big, WordOrder::little}) {
        SensorView view{state, now, 1000ms, written, order};
        view.offline = policy;
        view.substitute = -999;
        view.model_code = 7;
        INFO(name, ", policy ", int(policy), ", order ", int(order));
        check_every_range(map, view, RegisterTable::input);
        check_every_range(map, view, RegisterTable::holding);
      }
    }
  }
}

}  // namespace

TEST_CASE("register image: every range of the default maps reads as read_registers() does") {
  for (const char* model : {"h6", "h4360"}) {
    INFO(model);
    check_every_state(default_map(registered_families(), model));
  }
}

TEST_CASE("register image: a map with gaps, strings and written registers reads the same") {
  check_every_state(gappy_map());
}

TEST_CASE("register image: age_ms moves at every read, and a sensor going stale is seen") {
  const RegisterMap map = gappy_map();
  const auto now = SteadyClock::now();
  const SensorState state = sensor(now, 10ms, true);
  RegisterImage image;
  Words words(1);
  const auto age_at = [&](SteadyClock::time_point at) {
    SensorView view{state, at, 1000ms, {}};
    REQUIRE(image.read(map, view, RegisterTable::input, 5, words).has_value());
    return words[0];
  };
  CHECK(age_at(now) == 10);
  CHECK(age_at(now + 250ms) == 260);  // the same rendering, a new age
  // 1.2 s later the reading is stale and the sensor not heard from: the status register shows it.
  SensorView later{state, now + 1200ms, 1000ms, {}};
  REQUIRE(image.read(map, later, RegisterTable::input, 20, words).has_value());
  CHECK((words[0] & status_bit::stale) != 0);
  CHECK((words[0] & status_bit::online) == 0);
}

TEST_CASE("register image: clear() takes in a new snapshot") {
  const RegisterMap map = gappy_map();
  const auto now = SteadyClock::now();
  SensorState state = sensor(now, 10ms, true);
  RegisterImage image;
  Words words(1);
  REQUIRE(image.read(map, SensorView{state, now, 1000ms, {}}, RegisterTable::input, 0, words));
  CHECK(std::int16_t(words[0]) == -1235);
  SensorState next = state;
  next.reading->angle_x = 1.0;
  REQUIRE(image.read(map, SensorView{next, now, 1000ms, {}}, RegisterTable::input, 0, words));
  CHECK(std::int16_t(words[0]) == -1235);  // still the rendering of the first snapshot
  image.clear();
  REQUIRE(image.read(map, SensorView{next, now, 1000ms, {}}, RegisterTable::input, 0, words));
  CHECK(std::int16_t(words[0]) == 100);
}
