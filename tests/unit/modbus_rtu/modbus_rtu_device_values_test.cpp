// A device profile's values in register maps: a map point names one by its name (`source =
// "filter_level"`, `write = "filter_level"`), matched with the sensor's profile when the map is
// checked (a value named temperature is the built-in temperature source, in degC); unknown names, writes of read-only values and names used on a sensor without such
// a value are reported at the map's line; a profile may not take a built-in's name.
#include <doctest/doctest.h>

#include <string>

#include "config/config_loader.h"
#include "gateway/gateway.h"
#include "mapping/map_access.h"
#include "unit/support/rtu_test_profile.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using tiltgate::test::ScratchDir;

namespace {

using test::kRtuTestProfile;
namespace value = test::rtu_test_value;

// A bus and one sensor of `model` with `keys`.
std::string config(std::string_view model, std::string_view keys) {
  return "[[bus]]\nname = \"b\"\nport = \"/dev/ttyUSB0\"\nprotocol = \"" +
         std::string(model == "modbus-rtu" ? "modbus-rtu" : "rieker") +
         "\"\n\n[[sensor]]\nname = \"tilt\"\nbus = \"b\"\nmodel = \"" + std::string(model) +
         "\"\naddress = 3\nunit_id = 1\n" + std::string(keys);
}

std::string point(std::string_view name, std::string_view table, int address,
                  std::string_view keys) {
  return "\n[[point]]\nname = \"" + std::string(name) + "\"\ntable = \"" + std::string(table) +
         "\"\naddress = " + std::to_string(address) + "\ntype = \"int16\"\n" + std::string(keys);
}

struct Plant {
  ScratchDir dir{"tiltgate-device-values"};
  std::string map_path;
  Expected<Config, ConfigErrors> load(std::string_view model, std::string_view map) {
    dir.write("device.toml", kRtuTestProfile);
    map_path = dir.write("map.toml", map);
    const std::string keys = model == "modbus-rtu"
                                 ? "device = \"device.toml\"\nmap = \"map.toml\"\n"
                                 : "map = \"map.toml\"\n";
    return load_config_file(dir.write("plant.toml", config(model, keys)), registered_families());
  }
};

std::string joined(const ConfigErrors& errors) {
  std::string out;
  for (const ConfigError& e : errors) out += e.to_string() + "\n";
  return out;
}

}  // namespace

TEST_CASE("a map shows and writes a device profile's values by their names") {
  Plant plant;
  const auto loaded = plant.load(
      "modbus-rtu", point("temperature", "input", 0, "source = \"temperature\"\nscale = 10\n") +
                        point("level", "input", 1, "source = \"filter_level\"\n") +
                        point("filter", "holding", 0, "write = \"filter_level\"\nmin = 1\nmax = 8\n"));
  REQUIRE_MESSAGE(loaded.has_value(), joined(loaded.error()));
  const RegisterMap map = map_for(registered_families(), loaded->sensors[0]);
  // The profile's temperature is the sensor's, in degC: the built-in source.
  const Point* temperature = map.find("temperature");
  REQUIRE(temperature != nullptr);
  CHECK(temperature->source == ValueSource::temperature);
  const Point* level = map.find("level");
  REQUIRE(level != nullptr);
  CHECK(level->source == ValueSource::device_value);
  CHECK(level->device_index == value::filter_level);
  const Point* filter = map.find("filter");
  REQUIRE(filter != nullptr);
  CHECK(filter->write == WriteTarget::device_value(value::filter_level));
  CHECK(filter->source == ValueSource::setting);  // shows the device's value

  SensorState state;
  state.reading = Reading{};
  state.reading->device_values = {1.0, 2.0, 21.5, 4.0, 7.0};
  state.reading->temperature_c = 21.5;  // as the driver takes it from the profile's value
  state.reading->taken = SteadyClock::now();
  state.online = true;
  const SensorView view{state, SteadyClock::now(), std::chrono::milliseconds(1000), {},
                        WordOrder::big};
  const auto input = read_registers(map, view, RegisterTable::input, 0, 2);
  REQUIRE(input.has_value());
  CHECK(*input == std::vector<std::uint16_t>{215, 4});
  const auto holding = read_registers(map, view, RegisterTable::holding, 0, 1);
  REQUIRE(holding.has_value());
  CHECK(*holding == std::vector<std::uint16_t>{4});
}

TEST_CASE("an unknown device value name is reported at the map's line with a guess") {
  Plant plant;
  const auto loaded =
      plant.load("modbus-rtu", point("t", "input", 0, "source = \"temprature\"\n") +
                                   point("f", "holding", 0, "write = \"filtr_level\"\nmin = 1\nmax = 8\n") +
                                   point("g", "input", 1, "source = \"humidity\"\n"));
  REQUIRE_FALSE(loaded.has_value());
  const ConfigErrors& errors = loaded.error();
  INFO(joined(errors));
  REQUIRE(errors.size() == 3);
  CHECK(errors[0].to_string() ==
        plant.map_path + ":7:1: point[0].source: \"temprature\" is not valid; did you mean "
                         "\"temperature\"?");
  CHECK(errors[1].to_string() ==
        plant.map_path + ":14:1: point[1].write: \"filtr_level\" is not valid; did you mean "
                         "\"filter_level\"?");
  CHECK(errors[2].to_string() ==
        plant.map_path + ":23:1: point[2].source: \"humidity\" is neither a built-in source nor "
                         "one of the sensor's own: angle_x, angle_y, temperature, "
                         "filter_level, serial_number");
}

TEST_CASE("a write of a read-only device value is refused at the map's line") {
  Plant plant;
  const auto loaded = plant.load(
      "modbus-rtu", point("t", "holding", 0, "write = \"temperature\"\nmin = 0\nmax = 50\n"));
  REQUIRE_FALSE(loaded.has_value());
  INFO(joined(loaded.error()));
  REQUIRE(loaded.error().size() == 1);
  CHECK(loaded.error()[0].to_string() ==
        plant.map_path + ":7:1: point[0].write: \"temperature\" is read-only in the sensor's "
                         "device profile (its [[value]] needs writable = true)");
}

TEST_CASE("a sensor without a device profile has no values of its own to name") {
  Plant plant;
  const auto loaded = plant.load("h6", point("t", "input", 0, "source = \"filter_level\"\n"));
  REQUIRE_FALSE(loaded.has_value());
  INFO(joined(loaded.error()));
  REQUIRE(loaded.error().size() == 1);
  CHECK(loaded.error()[0].line == 7);
  CHECK(loaded.error()[0].key == "point[0].source");
  CHECK(loaded.error()[0].message.find("\"filter_level\" is not valid, expected one of: angle_x") ==
        0);
}

TEST_CASE("a device profile value may not take a built-in source's or setting's name") {
  ScratchDir dir{"tiltgate-device-values"};
  std::string profile(kRtuTestProfile);
  profile += "\n[[value]]\nname = \"status\"\ntable = \"input\"\naddress = 7\ntype = \"uint16\"\n";
  profile += "\n[[value]]\nname = \"zero_x\"\ntable = \"input\"\naddress = 5\ntype = \"int16\"\n";
  const std::string device = dir.write("device.toml", profile);
  const auto loaded =
      load_config_file(dir.write("plant.toml", config("modbus-rtu", "device = \"device.toml\"\n")), registered_families());
  REQUIRE_FALSE(loaded.has_value());
  INFO(joined(loaded.error()));
  REQUIRE(loaded.error().size() == 2);
  CHECK(loaded.error()[0].file == device);
  CHECK(loaded.error()[0].key == "value[5].name");
  CHECK(loaded.error()[0].message.find("\"status\" is a built-in source") == 0);
  CHECK(loaded.error()[1].key == "value[6].name");
  CHECK(loaded.error()[1].message.find("\"zero_x\" is a built-in setting") == 0);
}
