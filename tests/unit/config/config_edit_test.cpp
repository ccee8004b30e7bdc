// A configuration file changed in place after `tiltgate set` moved a sensor: only the value's
// own text changes (or one line is added), so comments, order, layout and the other sensors
// stay as the engineer wrote them.
#include <doctest/doctest.h>

#include <sstream>
#include <string>
#include <vector>

#include "config/config_edit.h"

using namespace tiltgate;

namespace {

const std::string kConfig = R"(# plant line 1
[server]
listen = "0.0.0.0"   # all interfaces

[[bus]]
  name = "line1"      # the boom's bus
  port = "/dev/ttyUSB0"
  protocol = "rieker"

[[bus]]
name = "line2"
port = "/dev/ttyUSB1"
baud = 9_600 # slow cable

[[sensor]]
name = "boom"
bus = "line1"
address = 0xDF   # factory address
unit_id = 1
mounting = { swap_axes = true, rotate_deg = 223 }

[[sensor]]
name = "mast"
bus = "line1"
address = 223
unit_id = 2
)";

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The lines that differ, as "N: old -> new", for files of the same length.
std::vector<std::string> changed_lines(const std::string& before, const std::string& after) {
  const auto a = lines(before);
  const auto b = lines(after);
  REQUIRE(a.size() == b.size());
  std::vector<std::string> out;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i]) out.push_back(std::to_string(i + 1) + ": " + a[i] + " -> " + b[i]);
  return out;
}

}  // namespace

TEST_CASE("a sensor's new address replaces only its address value, comment and layout kept") {
  const auto edit = edit_sensor_address(kConfig, "boom", 7);
  REQUIRE(edit);
  CHECK(edit->old_value == "0xDF");
  CHECK(edit->line == 18);
  CHECK(changed_lines(kConfig, edit->text) ==
        std::vector<std::string>{"18: address = 0xDF   # factory address -> address = 7   # factory address"});

  // The other sensor at 223, and the inline table's 223, are left alone.
  const auto mast = edit_sensor_address(kConfig, "mast", 9);
  REQUIRE(mast);
  CHECK(changed_lines(kConfig, mast->text) == std::vector<std::string>{"25: address = 223 -> address = 9"});
}

TEST_CASE("a bus's new baud replaces its value, or is added under its name with its indent") {
  const auto slow = edit_bus_baud(kConfig, "line2", 19200);
  REQUIRE(slow);
  CHECK(slow->old_value == "9_600");
  CHECK(changed_lines(kConfig, slow->text) ==
        std::vector<std::string>{"13: baud = 9_600 # slow cable -> baud = 19200 # slow cable"});

  const auto added = edit_bus_baud(kConfig, "line1", 115200);
  REQUIRE(added);
  CHECK(added->old_value.empty());
  CHECK(added->line == 7);
  auto expected = lines(kConfig);
  expected.insert(expected.begin() + 6, "  baud = 115200");
  CHECK(lines(added->text) == expected);
}

TEST_CASE("a sensor or bus the file does not have, or a file that is not TOML, is an error") {
  CHECK(edit_sensor_address(kConfig, "jib", 7).error() == "no [[sensor]] named \"jib\"");
  CHECK(edit_bus_baud(kConfig, "line9", 9600).error() == "no [[bus]] named \"line9\"");
  CHECK(edit_sensor_address("[[sensor]\nname = 1", "boom", 7).error().find("not valid TOML") == 0);
  const std::string inline_bus = "bus = [{ name = \"line1\", port = \"/dev/ttyS0\" }]\n";
  CHECK(edit_bus_baud(inline_bus, "line1", 9600).error().find("inline table") != std::string::npos);
}

TEST_CASE("a sensor written as an inline table, non-ASCII text before its address, is edited in place") {
  // toml++ counts columns in code points: "ü" is one column but two bytes.
  const std::string text =
      "sensor = [{ name = \"Kranbrücke\", address = 5, unit_id = 5 },  # Ost\n"
      "          { name = \"Mast\", address = 5 }]\n";
  const auto edit = edit_sensor_address(text, "Kranbrücke", 12);
  REQUIRE(edit);
  CHECK(changed_lines(text, edit->text) ==
        std::vector<std::string>{"1: sensor = [{ name = \"Kranbrücke\", address = 5, unit_id = 5 },  # Ost"
                                 " -> sensor = [{ name = \"Kranbrücke\", address = 12, unit_id = 5 },  # Ost"});
}
