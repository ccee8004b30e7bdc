// [[sensor]] device = "FILE" on modbus-rtu sensors: a device profile resolved against the
// configuration file's folder, loaded with the configuration, its errors reported at their own
// file:line along with the configuration's; required on modbus-rtu, refused elsewhere.
#include <doctest/doctest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "config/config_loader.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using tiltgate::test::ScratchDir;

namespace {

std::string rtu_config(std::string_view sensor_keys) {
  return "[[bus]]\nname = \"rtu\"\nport = \"/dev/ttyUSB0\"\nprotocol = \"modbus-rtu\"\n\n"
         "[[sensor]]\nname = \"tilt\"\nbus = \"rtu\"\nmodel = \"modbus-rtu\"\naddress = 3\n"
         "unit_id = 1\n" +
         std::string(sensor_keys);
}

void write_file(const std::string& path, std::string_view text) {
  std::ofstream out(path);
  out << text;
}

constexpr std::string_view kProfile = R"([[read]]
table = "input"
address = 0
count = 4

[[value]]
name = "angle_x"
table = "input"
address = 0
type = "float32"
)";

}  // namespace

TEST_CASE("a modbus-rtu sensor's device profile is found next to the configuration file") {
  ScratchDir dir;
  write_file(dir.path("tilt.toml"), kProfile);
  const std::string config = dir.path("gateway.toml");
  write_file(config, rtu_config("device = \"tilt.toml\"\n"));
  auto loaded = load_config_file(config, registered_families());
  REQUIRE_MESSAGE(loaded.has_value(),
                  (loaded ? std::string() : loaded.error().front().to_string()));
  CHECK(loaded->sensors.at(0).family_options.text("device") == dir.path("tilt.toml"));
}

TEST_CASE("a device profile's errors are reported at their own file and line") {
  ScratchDir dir;
  write_file(dir.path("tilt.toml"),
             std::string(kProfile) + "\n[[value]]\nname = \"angle_y\"\ntable = \"input\"\n"
                                     "address = 40\ntype = \"float32\"\n");
  const std::string config = dir.path("gateway.toml");
  write_file(config, rtu_config("device = \"tilt.toml\"\nbogus = 1\n"));
  auto loaded = load_config_file(config, registered_families());
  REQUIRE_FALSE(loaded.has_value());
  REQUIRE(loaded.error().size() == 2);
  CHECK(loaded.error()[0].file == config);  // the configuration's own error, with it
  CHECK(loaded.error()[0].key == "sensor[0].bogus");
  CHECK(loaded.error()[1].file == dir.path("tilt.toml"));
  CHECK(loaded.error()[1].line == 15);  // angle_y's address, outside every read block
}

TEST_CASE("device is required on modbus-rtu sensors and refused on others") {
  auto missing = load_config_string(rtu_config(""), "rtu.toml", registered_families());
  REQUIRE_FALSE(missing.has_value());
  CHECK(missing.error().front().to_string() ==
        "rtu.toml:6:1: sensor[0].device: required key is missing on modbus-rtu sensors");
  auto unreadable = load_config_string(rtu_config("device = \"/nonexistent/tilt.toml\"\n"),
                                       "rtu.toml", registered_families());
  REQUIRE_FALSE(unreadable.has_value());
  CHECK(unreadable.error().front().file == "/nonexistent/tilt.toml");
}
