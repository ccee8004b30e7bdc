// What a person reads of a sensor's settings (settings/setting_actions.h): every setting of
// every family has a label, every value a command accepts an action named by what it does with
// its question, and each says whether the sensor's value is read back or last written.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "mapping/default_maps.h"
#include "modbus_rtu/profile_reader.h"
#include "settings/setting_actions.h"

using namespace tiltgate;

namespace {

const ModelDescriptor& model_named(std::string_view name) {
  for (const FamilyDescriptor* family : registered_families())
    for (const ModelDescriptor& model : family->models)
      if (model.name == name) return model;
  FAIL("no model " << name);
  throw;
}

// The settings of `model`'s built-in map, with their words for a sensor named boom.
std::vector<std::pair<SensorSetting, SettingWords>> worded(const RegisterMap& map,
                                                           const ModelDescriptor& model) {
  std::vector<std::pair<SensorSetting, SettingWords>> out;
  for (const SensorSetting& s : sensor_settings(map, registered_families()))
    out.emplace_back(s, setting_words(s, &model, {}, "boom"));
  return out;
}

const SettingWords& words_of(const std::vector<std::pair<SensorSetting, SettingWords>>& list,
                             std::string_view name) {
  const auto found = std::find_if(list.begin(), list.end(),
                                  [&](const auto& entry) { return entry.first.name == name; });
  REQUIRE(found != list.end());
  return found->second;
}

}  // namespace

TEST_CASE("every setting of every family has a label, every command value an action") {
  for (const FamilyDescriptor* family : registered_families()) {
    for (const ModelDescriptor& model : family->models) {
      for (const SettingDescriptor& setting : model.settings) {
        INFO(model.name << " " << setting.name);
        CHECK_FALSE(setting.label.empty());
        CHECK(setting.label != setting.name);
        if (setting.id != WriteTarget::command) {
          CHECK(setting.actions.empty());
          continue;
        }
        // Each whole value in the range is one action, with a name and a question that names
        // the sensor.
        std::vector<double> values;
        for (const CommandAction& action : setting.actions) {
          INFO(action.value);
          CHECK_FALSE(action.name.empty());
          CHECK(action.confirm.find("{sensor}") != std::string_view::npos);
          CHECK(action.confirm.back() != ' ');
          values.push_back(action.value);
        }
        std::vector<double> accepted;
        for (double v = setting.min; v <= setting.max; ++v) accepted.push_back(v);
        CHECK(values == accepted);
      }
    }
  }
}

TEST_CASE("a Rieker's command: zero until restart, zero permanently, restart, each its role") {
  const RegisterMap map = default_map(registered_families(), "h6");
  const auto list = worded(map, model_named("h6"));
  const SettingWords& command = words_of(list, "command");
  CHECK(command.label == "Command");
  REQUIRE(command.actions.size() == 3);
  CHECK(command.actions[0].value == 1);
  CHECK(command.actions[0].name == "Zero to the current angle (until restart)");
  CHECK(command.actions[0].confirm == "Zero boom to its current angle? Until the sensor restarts.");
  CHECK(command.actions[0].role == SettingRole::operator_);
  CHECK(command.actions[1].name == "Zero permanently");
  CHECK(command.actions[1].role == SettingRole::operator_);
  CHECK(command.actions[2].name == "Restart the sensor");
  CHECK(command.actions[2].confirm == "Restart boom? It does not answer until it has started again.");
  CHECK(command.actions[2].role == SettingRole::admin);
  CHECK(words_of(list, "filter").label == "Filter");
  CHECK(words_of(list, "bus_address").label == "Bus address");
  CHECK(words_of(list, "zero_x").label == "Zero, X axis");
  CHECK(words_of(list, "baud_code").label == "Baud rate");
  // The Rieker protocol reads no setting back.
  // Not a structured binding: INFO's lambda captures it, which clang refuses before C++20's fix.
  for (const auto& entry : list) {
    INFO(entry.first.name);
    CHECK_FALSE(entry.second.read_back);
  }
}

TEST_CASE("a Dyna's EEPROM settings are read back, its window's location and reset are not") {
  const RegisterMap map = default_map(registered_families(), "dyna");
  const auto list = worded(map, model_named("dyna"));
  for (std::string_view name : {"sensor_offset", "temperature_offset", "pwm_offset", "baud_code",
                                "bus_address", "eeprom_value"}) {
    INFO(name);
    CHECK(words_of(list, name).read_back);
  }
  CHECK_FALSE(words_of(list, "eeprom_location").read_back);
  const SettingWords& command = words_of(list, "command");
  CHECK_FALSE(command.read_back);
  REQUIRE(command.actions.size() == 1);
  CHECK(command.actions[0].name == "Reset the module");
  CHECK(command.actions[0].role == SettingRole::admin);
  CHECK(command.actions[0].confirm.rfind("Reset boom?", 0) == 0);
}

TEST_CASE("a profile's writable value is labelled by its label, else its name, and read back") {
  const std::string text = R"(
[[read]]
table = "holding"
address = 0
count = 2

[[value]]
name = "filter_level"
table = "holding"
address = 0
type = "uint16"
writable = true
label = "Filter time"

[[value]]
name = "tare"
table = "holding"
address = 1
type = "uint16"
writable = true
)";
  const auto profile = modbus_rtu::parse_device_profile(text, "p.toml");
  REQUIRE(profile.has_value());
  const std::vector<DeviceValue> values = modbus_rtu::device_values_of(*profile);
  REQUIRE(values.size() == 2);
  CHECK(values[0].label == "Filter time");
  CHECK(values[1].label == "tare");
  Point point;
  point.table = RegisterTable::holding;
  point.write = WriteTarget::device_value(0);
  SensorSetting setting;
  setting.name = "filter_level";
  setting.point = &point;
  const SettingWords words = setting_words(setting, nullptr, values, "boom");
  CHECK(words.label == "Filter time");
  CHECK(words.read_back);
  CHECK(words.actions.empty());
}

TEST_CASE("a profile's label is for writable values only, and not empty") {
  const std::string blocks = "[[read]]\ntable = \"holding\"\naddress = 0\ncount = 1\n";
  const auto read_only = modbus_rtu::parse_device_profile(
      blocks + "[[value]]\nname = \"a\"\ntable = \"holding\"\naddress = 0\ntype = \"uint16\"\n"
               "label = \"A\"\n",
      "p.toml");
  REQUIRE_FALSE(read_only.has_value());
  CHECK(read_only.error().front().to_string().find("label: applies to writable values") !=
        std::string::npos);
  const auto empty = modbus_rtu::parse_device_profile(
      blocks + "[[value]]\nname = \"a\"\ntable = \"holding\"\naddress = 0\ntype = \"uint16\"\n"
               "writable = true\nlabel = \"\"\n",
      "p.toml");
  REQUIRE_FALSE(empty.has_value());
  CHECK(empty.error().front().to_string().find("label: empty") != std::string::npos);
}

TEST_CASE("a question names the sensor wherever {sensor} stands") {
  CHECK(naming_sensor("Zero {sensor}? {sensor} restarts.", "boom") == "Zero boom? boom restarts.");
  CHECK(naming_sensor("no name", "boom") == "no name");
  CHECK(naming_sensor("", "boom").empty());
}
