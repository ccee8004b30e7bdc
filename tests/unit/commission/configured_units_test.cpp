// What a scan proposes to add to a configuration (commission/configured_units.h, and
// sensor_tables with it): no device the configuration has is offered again, and each new one
// gets a unit id no configured unit has, so its table can be added as it is (issue 54, defect 1).
#include <doctest/doctest.h>

#include "commission/configured_units.h"
#include "commission/scan_plan.h"
#include "config/config_loader.h"

using namespace tiltgate;

namespace {

// boom and jib at 5 and 6 on line1, mast with unit id 3 on line2, an aggregate at 4 and
// unit id 20 passed through on a Modbus RTU bus.
constexpr std::string_view kServed = R"([[bus]]
name = "line1"
port = "/dev/ttyUSB0"
protocol = "rieker"

[[bus]]
name = "line2"
port = "/dev/ttyUSB1"
protocol = "rieker"

[[bus]]
name = "rtu"
port = "/dev/ttyUSB2"
protocol = "modbus-rtu"
pass_through = [20]

[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 5
unit_id = 1

[[sensor]]
name = "jib"
bus = "line1"
model = "h6"
address = 6
unit_id = 2

[[sensor]]
name = "mast"
bus = "line2"
model = "h4360"
address = 5
unit_id = 3

[[aggregate]]
unit_id = 4
points = ["angle_x", "angle_y"]
sensors = ["boom", "jib"]
)";

Config served() {
  auto config = load_config_string(kServed, "served", registered_families());
  INFO((config ? std::string() : config.error().front().to_string()));
  REQUIRE(config.has_value());
  return *config;
}

FoundSensor found_at(std::uint32_t address) {
  FoundSensor s;
  s.address = address;
  s.baud = 125000;
  s.model = "h6";
  return s;
}

}  // namespace

TEST_CASE("the free unit ids are the lowest of 1..247 that nothing takes") {
  CHECK(free_unit_ids({}, 3) == std::vector<std::uint8_t>{1, 2, 3});
  CHECK(free_unit_ids({1, 2, 3, 5}, 3) == std::vector<std::uint8_t>{4, 6, 7});
  std::set<std::uint8_t> all_but_247;
  for (unsigned id = 1; id < 247; ++id) all_but_247.insert(static_cast<std::uint8_t>(id));
  CHECK(free_unit_ids(all_but_247, 2) == std::vector<std::uint8_t>{247});
  all_but_247.insert(247);
  CHECK(free_unit_ids(all_but_247, 1).empty());
}

TEST_CASE("a configuration's units: its sensors', aggregates' and pass-through ids on every bus") {
  const ConfiguredUnits units = configured_units(served(), "line1");
  CHECK(units.unit_ids == std::set<std::uint8_t>{1, 2, 3, 4, 20});
  CHECK(units.on_bus == std::map<std::uint32_t, std::string>{{5, "boom"}, {6, "jib"}});
  // mast is at 5 too, but on line2: another bus's address is not this bus's.
  CHECK(configured_units(served(), "line2").on_bus ==
        std::map<std::uint32_t, std::string>{{5, "mast"}});
}

TEST_CASE("a scan proposes no configured device again, and free unit ids for the new ones") {
  BusConfig line1 = served().buses[0];
  const ConfiguredUnits units = configured_units(served(), "line1");
  const std::vector<FoundSensor> found{found_at(5), found_at(6), found_at(7), found_at(8)};
  const std::vector<SensorTable> tables = sensor_tables(line1, found, {}, units);
  REQUIRE(tables.size() == 4);
  CHECK(tables[0].configured_as == "boom");
  CHECK(tables[0].text.empty());
  CHECK(tables[0].proposed_unit_id == 0);
  CHECK(tables[1].configured_as == "jib");
  CHECK(tables[1].text.empty());
  // 1, 2, 3 (mast, on the other bus) and 4 (the aggregate) are taken: 5, then 6, not 20's.
  CHECK(tables[2].configured_as.empty());
  CHECK(tables[2].proposed_unit_id == 5);
  CHECK(tables[2].text.find("unit_id = 5 ") != std::string::npos);
  CHECK(tables[3].proposed_unit_id == 6);

  // Added to the configuration, the new tables pass its checks as they are.
  std::string added(kServed);
  for (const SensorTable& table : tables) added += "\n" + table.text;
  auto config = load_config_string(added, "added", registered_families());
  INFO(added);
  CHECK(config.has_value());

  // --config-out says which are configured already and writes only the new ones.
  const std::string text = scan_config_text(line1, found, {}, units);
  CHECK(text.find("# Address 5: already configured as \"boom\": not added again.") !=
        std::string::npos);
  CHECK(text.find("# Address 6: already configured as \"jib\"") != std::string::npos);
  CHECK(text.find("name = \"sensor_5\"") == std::string::npos);
  CHECK(text.find("name = \"sensor_7\"") != std::string::npos);
}

TEST_CASE("with every unit id taken, a new device's table says so instead of taking one") {
  ConfiguredUnits full;
  for (unsigned id = 1; id <= 247; ++id) full.unit_ids.insert(static_cast<std::uint8_t>(id));
  const std::vector<SensorTable> tables =
      sensor_tables(served().buses[0], {found_at(7)}, {}, full);
  REQUIRE(tables.size() == 1);
  CHECK(tables[0].proposed_unit_id == 0);
  CHECK(tables[0].text.find("none of 1..247 is free") != std::string::npos);
  CHECK(tables[0].text.find("unit_id =") == std::string::npos);
}
