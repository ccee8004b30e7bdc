// What a console shows of a sensor's settings (settings/sensor_settings.h): each setting its map
// writes, once, with its role, range, units, description and the value the sensor holds; and
// how a failed write's answer becomes the outcome a door reports and the audit trail keeps
// (settings/setting_outcome.h).
#include <doctest/doctest.h>

#include <algorithm>

#include "mapping/default_maps.h"
#include "settings/sensor_settings.h"
#include "settings/setting_outcome.h"

using namespace tiltgate;
using Result = SettingOutcome::Result;

namespace {

const SensorSetting& named(const std::vector<SensorSetting>& settings, std::string_view name) {
  const auto found = std::find_if(settings.begin(), settings.end(),
                                  [&](const SensorSetting& s) { return s.name == name; });
  REQUIRE(found != settings.end());
  return *found;
}

}  // namespace

TEST_CASE("a sensor's settings are its map's, each with its role, range, units and meaning") {
  const RegisterMap map = default_map(registered_families(), "h6");
  const std::vector<SensorSetting> settings = sensor_settings(map, registered_families());
  std::vector<std::string> names;
  for (const SensorSetting& s : settings) names.push_back(s.name);
  CHECK(names == std::vector<std::string>{"filter", "zero_x", "zero_y", "command", "baud_code",
                                          "bus_address"});
  const SensorSetting& filter = named(settings, "filter");
  CHECK(filter.role == SettingRole::operator_);
  CHECK(filter.min == 1);
  CHECK(filter.max == 6);
  CHECK(filter.description == "Set Filter Response 1 (fast, noisy) .. 6 (slow, quiet)");
  CHECK(filter.point == map.find("filter"));
  const SensorSetting& zero = named(settings, "zero_x");
  CHECK(zero.role == SettingRole::operator_);
  CHECK(zero.min == -180);
  CHECK(zero.max == 180);
  CHECK(zero.units == "deg");
  const SensorSetting& address = named(settings, "bus_address");
  CHECK(address.role == SettingRole::admin);
  CHECK(address.max == 65000);
  CHECK(named(settings, "command").role == SettingRole::admin);
  // Without the sensor's state no value is known.
  CHECK_FALSE(filter.value.has_value());
}

TEST_CASE("with the sensor's settings record, each setting carries its value when known") {
  const RegisterMap map = default_map(registered_families(), "h6");
  SensorState state;
  state.settings.set(WriteTarget::filter, 4);
  state.settings.set(WriteTarget::bus_address, 223);
  const std::vector<SensorSetting> settings = sensor_settings(map, registered_families(), &state);
  CHECK(named(settings, "filter").value == 4.0);
  CHECK(named(settings, "bus_address").value == 223.0);
  CHECK_FALSE(named(settings, "zero_x").value.has_value());
}

TEST_CASE("a write's failure: no answer is a time-out, the sensor's refusal a NAK with its code") {
  const SettingOutcome silent = outcome_of({WriteErrorKind::no_response, "unlock: timeout"});
  CHECK(silent.result == Result::timeout);
  CHECK(silent.detail == "unlock: timeout");
  CHECK(audit_result(silent) == "timeout");

  WriteError nak{WriteErrorKind::rejected, "command: NAK 3 (data invalid)"};
  nak.nak = 3;
  const SettingOutcome refused_data = outcome_of(nak);
  CHECK(refused_data.result == Result::nak);
  CHECK(refused_data.code == std::uint8_t(3));
  CHECK(audit_result(refused_data) == "nak 0x03");

  const SettingOutcome exception =
      outcome_of({WriteErrorKind::device_exception, "the device answered exception 03", 3});
  CHECK(exception.result == Result::nak);
  CHECK(audit_result(exception) == "nak 0x03");

  // A reply that is not the acknowledgement (the Dyna's only refusal): a NAK without a code.
  const SettingOutcome no_ack = outcome_of({WriteErrorKind::refused, "command: no ACK"});
  CHECK(no_ack.result == Result::nak);
  CHECK_FALSE(no_ack.code.has_value());
  CHECK(audit_result(no_ack) == "nak");
}

TEST_CASE("a busy sensor's NAK is a NAK, a bus too busy to start the write in time a time-out") {
  WriteError busy{WriteErrorKind::busy, "command: NAK 5 (busy)"};
  busy.nak = 5;
  CHECK(audit_result(outcome_of(busy)) == "nak 0x05");
  const SettingOutcome late =
      outcome_of({WriteErrorKind::busy, "bus too busy: write not started in time"});
  CHECK(late.result == Result::timeout);
}

TEST_CASE("a value the driver refuses before sending is refused, with why") {
  const SettingOutcome range = outcome_of({WriteErrorKind::bad_value, "filter response must be 1..6"});
  CHECK(range.result == Result::refused);
  CHECK(audit_result(range) == "refused: filter response must be 1..6");
  CHECK(outcome_of({WriteErrorKind::not_supported, "single-axis sensor has no Y zero"}).result ==
        Result::refused);
}

TEST_CASE("who may write a value: the setting's role, or operator for one of its operator_values") {
  const RegisterMap map = default_map(registered_families(), "h6");
  const std::vector<SensorSetting> settings = sensor_settings(map, registered_families());
  const SensorSetting& command = named(settings, "command");
  CHECK(command.operator_values == std::vector<double>{1, 2});
  CHECK(role_to_write(command, 1) == SettingRole::operator_);  // zero to the current angle
  CHECK(role_to_write(command, 2) == SettingRole::operator_);
  CHECK(role_to_write(command, 3) == SettingRole::admin);      // restart
  CHECK(role_to_write(named(settings, "filter"), 3) == SettingRole::operator_);
  CHECK(role_to_write(named(settings, "bus_address"), 1) == SettingRole::admin);
}
