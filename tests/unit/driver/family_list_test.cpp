// The registered families fit together: the config, the map files and the driver registry find
// protocols, models and settings by name across every family, so no name may mean two things.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "driver/family.h"
#include "driver/family_commands.h"
#include "mapping/register_map.h"

using namespace tiltgate;

namespace {

// The folders families/families.cmake names, as the build passes them: "a,b,c".
std::vector<std::string> family_folders() {
  std::vector<std::string> folders;
  std::string_view list = TILTGATE_FAMILY_FOLDERS;
  while (!list.empty()) {
    const std::size_t comma = list.find(',');
    folders.emplace_back(list.substr(0, comma));
    list = comma == std::string_view::npos ? std::string_view{} : list.substr(comma + 1);
  }
  return folders;
}

}  // namespace

TEST_CASE("the registered families are every family the build names, each once") {
  const std::vector<std::string> folders = family_folders();
  REQUIRE_FALSE(folders.empty());
  const FamilyList families = registered_families();
  CHECK(families.size() == folders.size());
  std::set<const FamilyDescriptor*> descriptors;
  std::set<std::string_view> names;
  std::set<std::string_view> sim_commands;
  const FamilyCommandsList commands = registered_family_commands();
  REQUIRE(commands.size() == families.size());
  for (std::size_t i = 0; i < families.size(); ++i) {
    const FamilyDescriptor* family = families[i];
    REQUIRE(family != nullptr);
    INFO("family ", std::string(family->name));
    CHECK(descriptors.insert(family).second);
    CHECK(names.insert(family->name).second);
    REQUIRE(commands[i] != nullptr);
    CHECK(commands[i]->family == family);
    CHECK(sim_commands.insert(commands[i]->simulator.command).second);
  }
}

TEST_CASE("no two families use one protocol or model name") {
  std::map<std::string_view, std::string_view> protocol_family;
  std::map<std::string_view, std::string_view> model_family;
  for (const FamilyDescriptor* family : registered_families()) {
    for (const ProtocolDescriptor& protocol : family->protocols) {
      INFO("protocol ", std::string(protocol.name), " of ", std::string(family->name));
      CHECK(protocol_family.emplace(protocol.name, family->name).second);
    }
    for (const ModelDescriptor& model : family->models) {
      INFO("model ", std::string(model.name), " of ", std::string(family->name));
      CHECK(model_family.emplace(model.name, family->name).second);
    }
  }
  CHECK_FALSE(protocol_family.empty());
}

TEST_CASE("a setting name means one id and an id one name, in every family") {
  std::map<std::string_view, unsigned> id_of;
  std::map<unsigned, std::string_view> name_of;
  for (const SettingDescriptor& setting : kCommonSettings) {
    id_of[setting.name] = setting.id.id;
    name_of[setting.id.id] = setting.name;
    CHECK(setting.id.id < kFirstFamilySetting);
  }
  for (const FamilyDescriptor* family : registered_families()) {
    for (const ModelDescriptor& model : family->models) {
      for (const SettingDescriptor& setting : model.settings) {
        INFO("setting ", std::string(setting.name), " of model ", std::string(model.name));
        CHECK(setting.id.id < kSettingIdCount);
        const auto [by_name, new_name] = id_of.emplace(setting.name, setting.id.id);
        CHECK(by_name->second == setting.id.id);
        const auto [by_id, new_id] = name_of.emplace(setting.id.id, setting.name);
        CHECK(by_id->second == setting.name);
        // A family's own setting takes an id above the common block's.
        if (new_id) CHECK(setting.id.id >= kFirstFamilySetting);
      }
    }
  }
}

TEST_CASE("each family's demo sensors are its own models, with files only for its own keys") {
  for (const FamilyCommands* commands : registered_family_commands()) {
    const FamilyDescriptor* family = commands->family;
    INFO("family ", std::string(family->name));
    const DemoBus& demo = commands->demo;
    if (demo.sensors.empty()) continue;  // the demo gives such a family no bus
    const ProtocolEntry protocol = find_protocol(registered_families(), demo.protocol);
    CHECK(protocol.family == family);
    CHECK_FALSE(demo.examples.empty());
    for (const DemoSensor& sensor : demo.sensors) {
      INFO("demo sensor ", std::string(sensor.name));
      CHECK(find_model(registered_families(), sensor.model).family == family);
      std::set<std::string_view> keys;
      for (const DemoFile& file : sensor.files) {
        CHECK(has_sensor_key(*family, file.key));
        CHECK(keys.insert(file.key).second);
        CHECK_FALSE(file.contents.empty());
      }
      // A key the family requires has nothing else to come from in the demo.
      for (std::string_view required : required_sensor_keys(*family))
        CHECK(keys.count(required) == 1);
    }
  }
}

// The settings' ranges live in one place, the family's descriptor: every model's built-in map
// serves each setting it accepts on a holding register with exactly that range and unit, and
// every holding register that writes names a setting the model lists.
TEST_CASE("each model's built-in map serves its settings with the descriptor's range") {
  for (const FamilyDescriptor* family : registered_families()) {
    for (const ModelDescriptor& model : family->models) {
      INFO(model.name);
      const RegisterMap map = model.default_map();
      for (const SettingDescriptor& setting : model.settings) {
        INFO(setting.name);
        CHECK(setting.min <= setting.max);
        if (setting.type == SettingType::integer) {
          CHECK(setting.min == std::trunc(setting.min));
          CHECK(setting.max == std::trunc(setting.max));
        }
        const Point* served = nullptr;
        for (const Point& p : map.points())
          if (p.write == setting.id) served = &p;
        REQUIRE(served != nullptr);
        CHECK(served->min == setting.min);
        CHECK(served->max == setting.max);
        CHECK(served->units == setting.unit);
        CHECK_FALSE(setting.description.empty());
      }
      for (const Point& p : map.points()) {
        if (!p.write) continue;
        INFO(p.name);
        const bool listed = std::any_of(model.settings.begin(), model.settings.end(),
                                        [&](const SettingDescriptor& s) { return s.id == *p.write; });
        CHECK(listed);
      }
    }
  }
}

// A dual-axis model's built-in map says how its Y angle comes about as it says the X's: the
// Modbus RTU device's both come from its profile, not from a zero offset it does not have.
TEST_CASE("each dual-axis model's built-in map describes its Y angle as its X angle") {
  for (const FamilyDescriptor* family : registered_families()) {
    for (const ModelDescriptor& model : family->models) {
      INFO(model.name);
      const RegisterMap map = model.default_map();
      const Point* x = map.find("angle_x");
      const Point* y = map.find("angle_y");
      REQUIRE(x != nullptr);
      REQUIRE(y != nullptr);
      if (y->description.starts_with("NaN")) continue;  // single axis
      std::string as_x = x->description;
      for (std::size_t at = as_x.find("_x"); at != std::string::npos; at = as_x.find("_x", at))
        as_x.replace(at, 2, "_y");
      if (as_x.starts_with("X ")) as_x.replace(0, 1, "Y");
      CHECK(y->description == as_x);
    }
  }
}
