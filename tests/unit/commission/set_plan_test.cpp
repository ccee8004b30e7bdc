// `tiltgate set SETTING VALUE...` as the writes each family's driver gets: the command line's
// words through the family's descriptor (baud codes, commands, compound settings), with usage
// errors that name what the model has.
#include <doctest/doctest.h>

#include <vector>

#include "driver/family.h"
#include "driver/family_commands.h"
#include "commission/set_plan.h"
#include "spectron/setting_ids.h"

using namespace tiltgate;

namespace {

SetTarget target_for(std::string_view protocol, std::string_view model,
                     std::span<const DeviceValue> device_values = {}) {
  const FamilyList families = registered_families();
  const ProtocolEntry p = find_protocol(families, protocol);
  const ModelEntry m = find_model(families, model);
  REQUIRE(p.protocol);
  REQUIRE(m.model);
  REQUIRE(p.family == m.family);
  return SetTarget{find_commands(registered_family_commands(), m.family), p.protocol, m.model,
                   device_values};
}

SetPlan plan(const SetTarget& target, std::vector<std::string> words, bool permanent = false) {
  auto result = plan_setting(target, SetArguments{std::move(words), permanent});
  REQUIRE_MESSAGE(result, (result ? "" : result.error()));
  return *result;
}

std::string usage_error(const SetTarget& target, std::vector<std::string> words,
                        bool permanent = false) {
  auto result = plan_setting(target, SetArguments{std::move(words), permanent});
  REQUIRE_FALSE(result);
  return result.error();
}

struct Write {
  WriteTarget target;
  double value;
};

void check_writes(const SetPlan& p, std::vector<Write> expected) {
  REQUIRE(p.writes.size() == expected.size());
  REQUIRE(p.write_names.size() == expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    CHECK(p.writes[i].target == expected[i].target);
    CHECK(p.writes[i].value == expected[i].value);
  }
}

bool contains(const std::string& text, std::string_view part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("set on a Rieker H6: the common settings, its baud codes and its commands") {
  const SetTarget h6 = target_for("rieker", "h6");
  const SetPlan address = plan(h6, {"address", "7"});
  check_writes(address, {{WriteTarget::bus_address, 7}});
  CHECK(address.new_address == 7u);
  CHECK_FALSE(address.restarts);

  // 115200 baud is Set Baud's code 3; the sensor takes it at its restart, which follows.
  const SetPlan baud = plan(h6, {"baud", "115200"});
  check_writes(baud, {{WriteTarget::baud_code, 3}, {WriteTarget::command, 3}});
  CHECK(baud.new_baud == 115200u);
  CHECK(baud.restarts);
  CHECK_FALSE(baud.new_address);

  check_writes(plan(h6, {"filter", "4"}), {{WriteTarget::filter, 4}});
  check_writes(plan(h6, {"zero-x", "-1.5"}), {{WriteTarget::zero_x, -1.5}});
  check_writes(plan(h6, {"zero_y", "2.25"}), {{WriteTarget::zero_y, 2.25}});
  check_writes(plan(h6, {"zero-here"}), {{WriteTarget::command, 1}});
  check_writes(plan(h6, {"zero-here"}, true), {{WriteTarget::command, 2}});
  const SetPlan restart = plan(h6, {"restart"});
  check_writes(restart, {{WriteTarget::command, 3}});
  CHECK(restart.restarts);
}

TEST_CASE("set on a single-axis H4360 has no zero-y, and suggests what it may have meant") {
  const SetTarget h4360 = target_for("rieker", "h4360");
  const std::string error = usage_error(h4360, {"zero-y", "1"});
  CHECK(contains(error, "unknown setting \"zero-y\""));
  CHECK(contains(error, "did you mean \"zero-x\"?"));
  CHECK(contains(error, "the settings of a h4360: address N, baud RATE, filter N, zero-x DEG, "
                        "zero-here [--permanent], restart"));
  CHECK(contains(usage_error(h4360, {"filtr", "2"}), "did you mean \"filter\"?"));
}

TEST_CASE("set refuses a wrong count of values, a non-number, a stray --permanent and a foreign rate") {
  const SetTarget h6 = target_for("rieker", "h6");
  CHECK(contains(usage_error(h6, {"address"}), "address takes one value: tiltgate set address N"));
  CHECK(contains(usage_error(h6, {"restart", "now"}), "restart takes no value"));
  CHECK(contains(usage_error(h6, {"filter", "fast"}), "filter: \"fast\" is not a number"));
  CHECK(contains(usage_error(h6, {"filter", "2"}, true), "--permanent goes with zero-here only"));
  CHECK(contains(usage_error(h6, {"baud", "19201"}),
                 "baud: 19201 is not a rieker baud rate, expected one of 9600, 19200"));
  CHECK(contains(usage_error(h6, {}), "give a SETTING"));
}

TEST_CASE("set on a Dyna: eeprom LOCATION VALUE is two writes, restart is its reset, no zeroing") {
  const SetTarget dyna = target_for("spectron-modbus", "dyna");
  const SetPlan eeprom = plan(dyna, {"eeprom", "100", "1234"});
  check_writes(eeprom, {{spectron::setting::eeprom_location, 100},
                        {spectron::setting::eeprom_value, 1234}});
  CHECK(eeprom.write_names == std::vector<std::string>{"eeprom_location", "eeprom_value"});
  check_writes(plan(dyna, {"sensor-offset", "5"}), {{spectron::setting::sensor_offset, 5}});
  check_writes(plan(dyna, {"restart"}), {{WriteTarget::command, 1}});
  // 28800 baud is location 22's code 10, in force after the reset that follows.
  check_writes(plan(dyna, {"baud", "28800"}), {{WriteTarget::baud_code, 10}, {WriteTarget::command, 1}});
  CHECK(contains(usage_error(dyna, {"baud", "115200"}), "not a spectron-modbus baud rate"));
  CHECK(contains(usage_error(dyna, {"zero-here"}), "unknown setting \"zero-here\""));
  CHECK(contains(usage_error(dyna, {"eeprom", "100"}), "eeprom takes 2 values: tiltgate set eeprom LOCATION VALUE"));
}

TEST_CASE("set on a Modbus RTU device: its profile's writable values by name, nothing else") {
  const std::vector<DeviceValue> values{{"angle_x", false}, {"filter_time", true, 0, 100},
                                        {"zero_offset", true}};
  const SetTarget rtu = target_for("modbus-rtu", "modbus-rtu", values);
  check_writes(plan(rtu, {"filter_time", "20"}), {{WriteTarget::device_value(1), 20}});
  check_writes(plan(rtu, {"zero-offset", "-3"}), {{WriteTarget::device_value(2), -3}});
  const std::string error = usage_error(rtu, {"angle_x", "1"});
  CHECK(contains(error, "the settings of a modbus-rtu: filter_time VALUE, zero_offset VALUE"));
  CHECK(contains(usage_error(rtu, {"address", "7"}), "unknown setting \"address\""));
  CHECK(contains(usage_error(rtu, {"restart"}), "unknown setting"));
}
