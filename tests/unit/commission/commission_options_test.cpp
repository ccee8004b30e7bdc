// The commissioning commands' bus options: checked as the config loader checks a [[bus]] and
// [[sensor]], each problem reported under the option's name.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "commission/commission_options.h"

using namespace tiltgate;

namespace {

BusOptions rieker_bus() {
  BusOptions o;
  o.port = "/dev/ttyUSB0";
  o.protocol = "rieker";
  o.addresses = {223};
  return o;
}

std::string all(const UsageErrors& errors) {
  std::string text;
  for (const std::string& e : errors) text += e + "\n";
  return text;
}

bool has_error_starting(const UsageErrors& errors, std::string_view prefix) {
  return std::any_of(errors.begin(), errors.end(),
                     [&](const std::string& e) { return e.rfind(prefix, 0) == 0; });
}

struct ConfigFile {
  std::filesystem::path path;
  explicit ConfigFile(const std::string& text) {
    path = std::filesystem::temp_directory_path() /
           ("commission_options_test_" + std::to_string(::getpid()) + ".toml");
    std::ofstream(path) << text;
  }
  ~ConfigFile() { std::filesystem::remove(path); }
};

constexpr const char* kPlant = R"(
[[bus]]
name = "line1"
port = "/dev/ttyUSB0"
protocol = "rieker"
baud = 38400

[[bus]]
name = "line2"
port = "/dev/ttyUSB1"
protocol = "spectron-9bit"
baud = 28800

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
unit_id = 1

[[sensor]]
name = "mast"
bus = "line1"
model = "h4360"
address = 101
unit_id = 2

[[sensor]]
name = "jib"
bus = "line2"
model = "dyna"
address = 1
unit_id = 3
)";

}  // namespace

TEST_CASE("a command-line bus takes the protocol's factory baud and its family's first model") {
  const auto target = resolve_bus_options(rieker_bus(), registered_families());
  REQUIRE_MESSAGE(target, all(target ? UsageErrors{} : target.error()));
  CHECK(target->bus.port == "/dev/ttyUSB0");
  CHECK(target->bus.protocol == "rieker");
  CHECK(target->bus.baud == 125000);
  REQUIRE(target->sensors.size() == 1);
  CHECK(target->sensors[0].model == "h6");
  CHECK(target->sensors[0].address == 223);

  BusOptions dyna = rieker_bus();
  dyna.protocol = "spectron-9bit";
  dyna.baud = 28800;
  dyna.addresses = {1, 2};
  const auto dynas = resolve_bus_options(dyna, registered_families());
  REQUIRE(dynas);
  CHECK(dynas->sensors.size() == 2);
  CHECK(dynas->sensors[1].model == "dyna");
  CHECK(dynas->sensors[1].address == 2);
}

TEST_CASE("a bad baud, address or framing on the command line is named by its option") {
  BusOptions o = rieker_bus();
  o.baud = 9601;
  o.addresses = {0, 70000};
  o.parity = "even";
  const auto target = resolve_bus_options(o, registered_families());
  REQUIRE_FALSE(target);
  INFO(all(target.error()));
  CHECK(has_error_starting(target.error(), "--baud: 9601 is not a rieker baud rate"));
  CHECK(has_error_starting(target.error(), "--address: 0 is out of range"));
  CHECK(has_error_starting(target.error(), "--address: 70000 is out of range"));
  CHECK(has_error_starting(target.error(), "--parity: applies to modbus-rtu buses only"));
}

TEST_CASE("an unknown protocol is reported once, without a follow-on model error") {
  BusOptions o = rieker_bus();
  o.protocol = "rieker-ascii";
  const auto target = resolve_bus_options(o, registered_families());
  REQUIRE_FALSE(target);
  INFO(all(target.error()));
  CHECK(target.error().size() == 1);
  CHECK(has_error_starting(target.error(), "--protocol:"));
}

TEST_CASE("a model from another family than the protocol's is refused under --model") {
  BusOptions o = rieker_bus();
  o.model = "dyna";
  const auto target = resolve_bus_options(o, registered_families());
  REQUIRE_FALSE(target);
  INFO(all(target.error()));
  CHECK(has_error_starting(target.error(), "--model:"));
}

TEST_CASE("--device goes to the family's own key reader: required by one family, refused by another") {
  BusOptions rtu = rieker_bus();
  rtu.protocol = "modbus-rtu";
  rtu.addresses = {1};
  const auto missing = resolve_bus_options(rtu, registered_families());
  REQUIRE_FALSE(missing);
  CHECK(has_error_starting(missing.error(), "--device: required key is missing"));

  rtu.device = std::string(TILTGATE_SOURCE_DIR) + "/examples/devices/rtu-inclinometer.toml";
  const auto given = resolve_bus_options(rtu, registered_families());
  REQUIRE_MESSAGE(given, all(given ? UsageErrors{} : given.error()));
  CHECK(given->sensors[0].family_options.text("device") == rtu.device);
  CHECK_FALSE(given->sensors[0].family_options.device_values().empty());

  BusOptions rieker = rieker_bus();
  rieker.device = rtu.device;
  const auto refused = resolve_bus_options(rieker, registered_families());
  REQUIRE_FALSE(refused);
  CHECK(has_error_starting(refused.error(), "--device: applies to model"));
}

TEST_CASE("a tty path with quotes and backslashes reaches the bus unchanged") {
  BusOptions o = rieker_bus();
  o.port = R"(/tmp/a "quoted" \ tty)";
  const auto target = resolve_bus_options(o, registered_families());
  REQUIRE(target);
  CHECK(target->bus.port == o.port);
}

TEST_CASE("--port takes a device server's URL, checked as the configuration's port is") {
  BusOptions o = rieker_bus();
  o.port = "rfc2217://192.168.1.20:4001";
  const auto target = resolve_bus_options(o, registered_families());
  REQUIRE(target);
  CHECK(target->bus.port == o.port);

  o.port = "tcp://192.168.1.20:70000";
  const auto bad = resolve_bus_options(o, registered_families());
  REQUIRE_FALSE(bad);
  INFO(all(bad.error()));
  CHECK(bad.error() ==
        UsageErrors{"--port: the port 70000 is out of range, expected 1..65535"});

  BusOptions nine_bit = rieker_bus();
  nine_bit.protocol = "spectron-9bit";
  nine_bit.baud = 9600;
  nine_bit.addresses = {1};
  nine_bit.port = "tcp://192.168.1.20:4001";
  const auto refused = resolve_bus_options(nine_bit, registered_families());
  REQUIRE_FALSE(refused);
  CHECK(has_error_starting(refused.error(), "--port: \"tcp://192.168.1.20:4001\": 9-bit framing "
                                            "needs a local serial port"));
}

TEST_CASE("bus options come from the command line or a configuration, never both") {
  BusOptions both = rieker_bus();
  both.config = "plant.toml";
  both.sensor = "boom";
  const auto mixed = resolve_bus_options(both, registered_families());
  REQUIRE_FALSE(mixed);
  CHECK(has_error_starting(mixed.error(), "--port: not with --config"));
  CHECK(has_error_starting(mixed.error(), "--protocol: not with --config"));
  CHECK(has_error_starting(mixed.error(), "--address: not with --sensor"));

  BusOptions neither;
  neither.addresses = {1};
  const auto none = resolve_bus_options(neither, registered_families());
  REQUIRE_FALSE(none);
  CHECK(has_error_starting(none.error(), "--port: required"));

  BusOptions no_address = rieker_bus();
  no_address.addresses.clear();
  const auto unaddressed = resolve_bus_options(no_address, registered_families());
  REQUIRE_FALSE(unaddressed);
  CHECK(has_error_starting(unaddressed.error(), "--address: required with --port"));

  BusOptions config_alone;
  config_alone.config = "plant.toml";
  const auto alone = resolve_bus_options(config_alone, registered_families());
  REQUIRE_FALSE(alone);
  CHECK(has_error_starting(alone.error(), "--config: give --sensor NAME"));

  BusOptions sensor_alone = rieker_bus();
  sensor_alone.sensor = "boom";
  const auto without_config = resolve_bus_options(sensor_alone, registered_families());
  REQUIRE_FALSE(without_config);
  CHECK(has_error_starting(without_config.error(), "--sensor: needs --config"));
}

TEST_CASE("--config with --sensor takes that sensor and its bus") {
  const ConfigFile file(kPlant);
  BusOptions o;
  o.config = file.path.string();
  o.sensor = "jib";
  const auto target = resolve_bus_options(o, registered_families());
  REQUIRE_MESSAGE(target, all(target ? UsageErrors{} : target.error()));
  CHECK(target->bus.name == "line2");
  CHECK(target->bus.baud == 28800);
  REQUIRE(target->sensors.size() == 1);
  CHECK(target->sensors[0].name == "jib");

  o.sensor = "jab";
  const auto unknown = resolve_bus_options(o, registered_families());
  REQUIRE_FALSE(unknown);
  CHECK(has_error_starting(unknown.error(), "--sensor:"));
  CHECK(all(unknown.error()).find("boom, mast, jib") != std::string::npos);
}

TEST_CASE("--config with --bus takes the bus's sensors, or those at the addresses given") {
  const ConfigFile file(kPlant);
  BusOptions o;
  o.config = file.path.string();
  o.bus = "line1";
  const auto whole = resolve_bus_options(o, registered_families());
  REQUIRE(whole);
  CHECK(whole->bus.port == "/dev/ttyUSB0");
  REQUIRE(whole->sensors.size() == 2);
  CHECK(whole->sensors[0].name == "boom");
  CHECK(whole->sensors[1].name == "mast");

  o.addresses = {101};
  const auto one = resolve_bus_options(o, registered_families());
  REQUIRE(one);
  REQUIRE(one->sensors.size() == 1);
  CHECK(one->sensors[0].name == "mast");

  o.addresses = {101, 5};
  const auto missing = resolve_bus_options(o, registered_families());
  REQUIRE_FALSE(missing);
  CHECK(has_error_starting(missing.error(), "--address: bus \"line1\""));

  o.addresses.clear();
  o.bus = "line9";
  const auto no_bus = resolve_bus_options(o, registered_families());
  REQUIRE_FALSE(no_bus);
  CHECK(has_error_starting(no_bus.error(), "--bus:"));
}

TEST_CASE("a configuration with errors is refused with its own places") {
  const ConfigFile file("[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\nbaud = 12\n");
  BusOptions o;
  o.config = file.path.string();
  o.bus = "line1";
  const auto target = resolve_bus_options(o, registered_families());
  REQUIRE_FALSE(target);
  INFO(all(target.error()));
  CHECK(all(target.error()).find(file.path.string() + ":4:") != std::string::npos);
}
