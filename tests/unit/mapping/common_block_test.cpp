// The built-in maps share one common block: the same points at the same addresses on every
// model, "not available" values where a model lacks a quantity or a setting, and holding
// registers that show the settings the driver knows.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mapping/common_block.h"
#include "mapping/model_capabilities.h"
#include "mapping/default_maps.h"
#include "mapping/map_access.h"
#include "mapping/value_codec.h"
#include "spectron/setting_ids.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using Words = std::vector<std::uint16_t>;

// A point as a PLC sees it: where, how wide, what type, under which name.
std::string layout(const Point& p) {
  return std::string(to_string(p.table)) + " " + std::to_string(p.address) + " " +
         std::to_string(p.words()) + " " + to_string(p.type) + " " + p.name;
}

// The points below the model-specific start, in table and address order.
std::vector<std::string> common_layout(std::string_view model) {
  std::vector<std::string> rows;
  const RegisterMap map = default_map(registered_families(), model);
  for (const Point& p : map.points())
    if (p.address < kModelSpecificStart) rows.push_back(layout(p));
  return rows;
}

SensorState online_state(SteadyClock::time_point now, double x, double y) {
  SensorState s;
  s.online = true;
  s.identity_known = true;
  Reading r;
  r.angle_x = x;
  r.angle_y = y;
  r.taken = now - 10ms;
  s.reading = r;
  return s;
}

Words read(const RegisterMap& map, const SensorView& view, RegisterTable table,
           std::uint16_t address, std::uint16_t count) {
  auto words = read_registers(map, view, table, address, count);
  REQUIRE(words.has_value());
  return *words;
}

float float_at(const Words& words, std::size_t at) {
  return get_float32(std::span<const std::uint16_t, 2>(words.data() + at, 2), WordOrder::big);
}

SensorView view_of(const SensorState& state, SteadyClock::time_point now, std::string_view model) {
  SensorView view{state, now, 1000ms, {}};
  view.model_code = find_model(registered_families(), model).model->model_code;
  return view;
}

}  // namespace

TEST_CASE("every model's map has the identical common block") {
  const auto h6 = common_layout("h6");
  CHECK(h6 == common_layout("h4360"));
  CHECK(h6 == common_layout("dyna"));
  // Contiguous: one read of input 0..51 and of holding 0..7 covers it on any model.
  for (std::string_view model : models_with_default_maps(registered_families())) {
    CAPTURE(model);
    const RegisterMap map = default_map(registered_families(), model);
    const auto now = SteadyClock::now();
    const SensorState state = online_state(now, 1, 2);
    CHECK(read_registers(map, view_of(state, now, model), RegisterTable::input, 0, 52));
    CHECK_FALSE(read_registers(map, view_of(state, now, model), RegisterTable::input, 52, 1));
    CHECK(read_registers(map, view_of(state, now, model), RegisterTable::holding, 0, 8));
    // Discrete inputs 0..12: online, the six alarm flags, wrong_device, standby, then the
    // displacement alarm, the danger level, an alarm unacknowledged and the clock.
    const auto bits = read_bits(map, view_of(state, now, model), RegisterTable::discrete, 0, 13);
    CHECK(bits.has_value());
    CHECK_FALSE(read_bits(map, view_of(state, now, model), RegisterTable::discrete, 13, 1));
    // Coil 0: the acknowledgement.
    CHECK(read_bits(map, view_of(state, now, model), RegisterTable::coil, 0, 1).has_value());
    CHECK_FALSE(read_bits(map, view_of(state, now, model), RegisterTable::coil, 1, 1));
    CHECK(map.validate(registered_families(), model).empty());
  }
  const RegisterMap dyna = default_map(registered_families(), "dyna");
  CHECK(dyna.find("raw_counts")->address == 100);
  CHECK(dyna.find("raw_temperature")->address == 102);
  CHECK(dyna.find("eeprom_location")->address == 103);
}

TEST_CASE("input 50 is the temperature in degC as float32, NaN where the sensor has none") {
  const auto now = SteadyClock::now();
  SensorState state = online_state(now, 1, 2);
  for (std::string_view model : {"h6", "dyna"}) {
    CAPTURE(model);
    const RegisterMap map = default_map(registered_families(), model);
    CHECK(std::isnan(float_at(read(map, view_of(state, now, model), RegisterTable::input, 50, 2), 0)));
  }
  state.reading->temperature_c = -12.25;
  const RegisterMap dyna = default_map(registered_families(), "dyna");
  CHECK(float_at(read(dyna, view_of(state, now, "dyna"), RegisterTable::input, 50, 2), 0) == -12.25f);
}

TEST_CASE("register 37 tells the model") {
  const auto now = SteadyClock::now();
  const SensorState state = online_state(now, 1, 2);
  for (const auto& expected : {std::pair("h6", 1), std::pair("h4360", 2), std::pair("dyna", 3)}) {
    const std::string_view model = expected.first;
    CAPTURE(model);
    CHECK(read(default_map(registered_families(), model), view_of(state, now, model), RegisterTable::input, 37, 1)[0] ==
          expected.second);
  }
}

TEST_CASE("a single-axis model's Y reads NaN and -32768") {
  const auto now = SteadyClock::now();
  const SensorState state = online_state(now, 12.5, NAN);
  for (std::string_view model : {"h4360", "dyna"}) {
    CAPTURE(model);
    const Words w = read(default_map(registered_families(), model), view_of(state, now, model), RegisterTable::input, 0, 6);
    CHECK(float_at(w, 0) == 12.5f);
    CHECK(std::isnan(float_at(w, 2)));
    CHECK(std::int16_t(w[4]) == 1250);
    CHECK(std::int16_t(w[5]) == -32768);
  }
}

TEST_CASE("holding registers read the unknown value before any write") {
  const auto now = SteadyClock::now();
  const SensorState state = online_state(now, 1, 2);
  for (std::string_view model : models_with_default_maps(registered_families())) {
    CAPTURE(model);
    const Words w = read(default_map(registered_families(), model), view_of(state, now, model), RegisterTable::holding,
                         0, 8);
    CHECK(w[0] == 0xFFFF);                                    // filter
    CHECK(std::isnan(float_at(w, 1)));  // zero_x
    CHECK(std::isnan(float_at(w, 3)));  // zero_y
    // command: "no command" where the model takes commands, else not available
    CHECK(w[5] == (model_accepts(registered_families(), model, WriteTarget::command) ? 0 : 0xFFFF));
    CHECK(w[6] == 0xFFFF);                                    // baud_code
    CHECK(w[7] == 0xFFFF);                                    // bus_address: not published
  }
  const Words dyna = read(default_map(registered_families(), "dyna"), view_of(state, now, "dyna"),
                          RegisterTable::holding, 100, 5);
  CHECK(dyna == Words{0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF, 0xFFFF});
}

TEST_CASE("holding registers show the settings the driver knows") {
  const auto now = SteadyClock::now();
  SensorState state = online_state(now, 1, 2);
  state.settings.set(WriteTarget::filter, 4);
  state.settings.set(WriteTarget::zero_x, -1.5);
  state.settings.set(WriteTarget::baud_code, 3);
  state.settings.set(WriteTarget::bus_address, 223);
  const Words h6 = read(default_map(registered_families(), "h6"), view_of(state, now, "h6"), RegisterTable::holding, 0, 8);
  CHECK(h6[0] == 4);
  CHECK(float_at(h6, 1) == -1.5f);
  CHECK(std::isnan(float_at(h6, 3)));  // zero_y still unknown
  CHECK(h6[6] == 3);
  CHECK(h6[7] == 223);

  state.settings.set(spectron::setting::sensor_offset, 7);
  state.settings.set(spectron::setting::eeprom_location, 20);
  state.settings.set(spectron::setting::eeprom_value, 355);
  const RegisterMap dyna = default_map(registered_families(), "dyna");
  const Words d = read(dyna, view_of(state, now, "dyna"), RegisterTable::holding, 0, 8);
  CHECK(d[0] == 0xFFFF);  // a Dyna has no filter, whatever the state says
  CHECK(std::isnan(float_at(d, 1)));
  CHECK(d[7] == 223);
  CHECK(read(dyna, view_of(state, now, "dyna"), RegisterTable::holding, 100, 5) ==
        Words{7, 0xFFFF, 0xFFFF, 20, 355});
}

TEST_CASE("a setting the model does not have refuses writes as an illegal address") {
  const std::uint16_t one[] = {1};
  CHECK(plan_register_write(default_map(registered_families(), "dyna"), WordOrder::big, 0, one).error() ==
        MapFault::illegal_address);  // filter
  const std::uint16_t zero[] = {0, 0};
  CHECK(plan_register_write(default_map(registered_families(), "dyna"), WordOrder::big, 1, zero).error() ==
        MapFault::illegal_address);  // zero_x
  CHECK(plan_register_write(default_map(registered_families(), "h4360"), WordOrder::big, 3, zero).error() ==
        MapFault::illegal_address);  // zero_y
  CHECK(plan_register_write(default_map(registered_families(), "h6"), WordOrder::big, 3, zero).has_value());
}
