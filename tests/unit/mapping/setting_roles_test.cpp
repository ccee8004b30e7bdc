// Who may change a setting (issue 42's roles): a writable point's `role` in a map file and a
// device profile's writable value's, admin when not given, each mistake reported at its file,
// line and key; the built-in maps' operator settings (zero and filter) and admin ones (what can
// lose the sensor); the role column of `tiltgate map`'s CSV.
#include <doctest/doctest.h>

#include <map>
#include <string>

#include "config/config_loader.h"
#include "gateway/gateway.h"
#include "mapping/default_maps.h"
#include "mapping/map_export.h"
#include "unit/support/config_text.h"
#include "unit/support/rtu_test_profile.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using test::only_error;

namespace {

// Lines 1..9: a bus and one sensor of `model` with `keys`; an inline map from line 10 on.
std::string config_with(std::string_view rest, std::string_view model = "h6",
                        std::string_view keys = "") {
  const bool rtu = model == "modbus-rtu";
  return "[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\nprotocol = \"" +
         std::string(rtu ? "modbus-rtu" : "rieker") + "\"\n[[sensor]]\nname = \"s\"\n" +
         "bus = \"line1\"\nmodel = \"" + std::string(model) + "\"\naddress = 3\nunit_id = 1\n" +
         std::string(keys) + std::string(rest);
}

// An inline map's writable point (8 lines, the last `role` when given), from its
// [[sensor.map.point]] header on.
std::string writable_point(std::string_view name, std::string_view write, std::string_view role) {
  std::string text = "[[sensor.map.point]]\nname = \"" + std::string(name) +
                     "\"\ntable = \"holding\"\naddress = 20\ntype = \"uint16\"\nwrite = \"" +
                     std::string(write) + "\"\nmin = 0\nmax = 20\n";
  if (!role.empty()) text += "role = \"" + std::string(role) + "\"\n";
  return text;
}

RegisterMap map_of(const std::string& config_text) {
  return map_for(registered_families(), test::loads(config_text).sensors.front());
}

// Each writable point's role by name.
std::map<std::string, SettingRole> roles_of(const RegisterMap& map) {
  std::map<std::string, SettingRole> roles;
  for (const Point& p : map.points())
    if (p.write) roles[p.name] = p.role;
  return roles;
}

constexpr auto op = SettingRole::operator_;
constexpr auto admin = SettingRole::admin;

}  // namespace

TEST_CASE("a map file's role marks a writable point as an operator's or an admin's") {
  CHECK(map_of(config_with(writable_point("f", "filter", "operator"))).find("f")->role == op);
  CHECK(map_of(config_with(writable_point("f", "filter", "admin"))).find("f")->role == admin);
}

TEST_CASE("a custom setting without a role needs an admin") {
  const RegisterMap map = map_of(config_with(writable_point("f", "filter", "")));
  CHECK(map.find("f")->role == admin);
}

TEST_CASE("a role that is neither operator nor admin is reported at its line with a guess") {
  const ConfigError error = only_error(config_with(writable_point("f", "filter", "oprator")));
  CHECK(error.line == 19);
  CHECK(error.key == "sensor[0].map.point[0].role");
  CHECK(error.message == "\"oprator\" is not valid; did you mean \"operator\"?");
}

TEST_CASE("a role on a read-only point is reported: only a setting has one") {
  const ConfigError error = only_error(config_with(
      "[[sensor.map.point]]\nname = \"t\"\ntable = \"input\"\naddress = 0\ntype = \"float32\"\n"
      "source = \"tilt\"\nrole = \"operator\"\n"));
  CHECK(error.line == 17);
  CHECK(error.key == "sensor[0].map.point[0].role");
  CHECK(error.message == "applies to writable points (write = \"...\") only");
}

TEST_CASE("built-in maps: zero and filter are an operator's, what can lose the sensor an admin's") {
  const auto builtin = [](std::string_view model) {
    return roles_of(default_map(registered_families(), model));
  };
  // Rieker: the command restarts the sensor (3), the baud and the address can lose it.
  CHECK(builtin("h6") == std::map<std::string, SettingRole>{{"filter", op},
                                                            {"zero_x", op},
                                                            {"zero_y", op},
                                                            {"command", admin},
                                                            {"baud_code", admin},
                                                            {"bus_address", admin}});
  CHECK(builtin("h4360") == std::map<std::string, SettingRole>{{"filter", op},
                                                               {"zero_x", op},
                                                               {"command", admin},
                                                               {"baud_code", admin},
                                                               {"bus_address", admin}});
  // Dyna: every setting is an EEPROM write or the reset.
  for (const auto& entry : builtin("dyna")) {
    INFO(entry.first);
    CHECK(entry.second == admin);
  }
  CHECK(builtin("dyna").size() == 8);
  // A generic Modbus RTU device's settings are its profile's: its built-in map has none.
  CHECK(builtin("modbus-rtu").empty());
}

TEST_CASE("the CSV export shows each writable point's role, nothing for a read-only one") {
  const RegisterMap map = default_map(registered_families(), "h6");
  const std::string csv = export_csv({{1, "boom", "h6", &map}});
  CHECK(csv.find("\n1,filter,holding,0,1,uint16,rw,") != std::string::npos);
  CHECK(csv.find(",40001,operator\n") != std::string::npos);   // filter
  CHECK(csv.find(",40006,admin (operator: 1 2)\n") != std::string::npos);  // command: 1, 2 zero
  CHECK(csv.find(",40008,admin\n") != std::string::npos);      // bus_address
  CHECK(csv.find(",30001,\n") != std::string::npos);           // angle_x: read-only
}

namespace {

// kRtuTestProfile with `role` given to filter_level (after its `max`).
std::string profile_with_role(std::string_view role) {
  std::string profile = test::kRtuTestProfile;
  const std::string anchor = "max = 20\n";
  profile.insert(profile.find(anchor) + anchor.size(), "role = \"" + std::string(role) + "\"\n");
  return profile;
}

struct RtuPlant {
  test::ScratchDir dir{"tiltgate-setting-roles"};
  std::string profile_path;
  std::string config(std::string_view profile, std::string_view map) {
    profile_path = dir.write("device.toml", profile);
    return config_with(map, "modbus-rtu", "device = \"" + profile_path + "\"\n");
  }
};

}  // namespace

TEST_CASE("a device profile's role is what a map point writing the value takes, unless it has one") {
  RtuPlant plant;
  const std::string profile = profile_with_role("operator");
  CHECK(map_of(plant.config(profile, writable_point("f", "filter_level", ""))).find("f")->role ==
        op);
  CHECK(map_of(plant.config(profile, writable_point("f", "filter_level", "admin")))
            .find("f")
            ->role == admin);
  // serial_number is writable in the profile, with no role: an admin's.
  CHECK(map_of(plant.config(profile, writable_point("n", "serial_number", ""))).find("n")->role ==
        admin);
  CHECK(map_of(plant.config(test::kRtuTestProfile, writable_point("f", "filter_level", "")))
            .find("f")
            ->role == admin);
}

TEST_CASE("a device profile's role on a read-only value, or an unknown one, is reported at its line") {
  RtuPlant plant;
  std::string read_only = test::kRtuTestProfile;
  const std::string anchor = "scale = 0.1\n";  // temperature, line 28
  read_only.insert(read_only.find(anchor) + anchor.size(), "role = \"operator\"\n");
  const ConfigError on_read_only = only_error(plant.config(read_only, ""));
  CHECK(on_read_only.file == plant.profile_path);
  CHECK(on_read_only.line == 29);
  CHECK(on_read_only.key == "value[2].role");
  CHECK(on_read_only.message == "applies to writable values (writable = true) only");

  const ConfigError unknown = only_error(plant.config(profile_with_role("boss"), ""));
  CHECK(unknown.file == plant.profile_path);
  CHECK(unknown.key == "value[3].role");
  CHECK(unknown.message.find("\"operator\" or \"admin\"") != std::string::npos);
}

TEST_CASE("a map file's operator_values let an operator write those values of an admin setting") {
  const RegisterMap map =
      map_of(config_with(writable_point("c", "command", "") + "operator_values = [1, 2]\n"));
  CHECK(map.find("c")->role == admin);
  CHECK(map.find("c")->operator_values == std::vector<double>{1, 2});
}

TEST_CASE("operator_values outside the point's range, or on a read-only point, are reported") {
  const ConfigError outside = only_error(
      config_with(writable_point("c", "command", "") + "operator_values = [1, 21]\n"));
  CHECK(outside.line == 19);
  CHECK(outside.key == "sensor[0].map.point[0].operator_values");
  CHECK(outside.message == "21 is outside the point's min..max (0..20)");
  const ConfigError read_only = only_error(config_with(
      "[[sensor.map.point]]\nname = \"t\"\ntable = \"input\"\naddress = 0\ntype = \"float32\"\n"
      "source = \"tilt\"\noperator_values = [1]\n"));
  CHECK(read_only.key == "sensor[0].map.point[0].operator_values");
  CHECK(read_only.message == "applies to writable points (write = \"...\") only");
}

TEST_CASE("built-in Rieker maps: an operator may zero to the current angle (command 1, 2), not restart (3)") {
  for (std::string_view model : {"h6", "h4360"}) {
    INFO(model);
    const RegisterMap map = default_map(registered_families(), model);
    CHECK(map.find("command")->role == admin);
    CHECK(map.find("command")->operator_values == std::vector<double>{1, 2});
  }
}
