// Register maps in configuration: map files next to the config, inline maps, their errors at
// the right file and line, the example maps, and docs/default-maps.md kept in step.
#include <doctest/doctest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "config/config_loader.h"
#include "mapping/map_definition.h"
#include "mapping/map_export.h"

using namespace tiltgate;
namespace fs = std::filesystem;

namespace {

std::string joined(const ConfigErrors& errors) {
  std::string out;
  for (const ConfigError& e : errors) out += e.to_string() + "\n";
  return out;
}

// A directory of its own under /tmp, removed afterwards.
struct ScratchDir {
  fs::path path;
  ScratchDir() {
    static int counter = 0;
    path = fs::temp_directory_path() /
           ("tiltgate-map-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::create_directories(path / "maps");
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path, ignored);
  }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return (path / name).string();
  }
};

// Lines 1..9: a bus and one sensor of `model`; `rest` starts at line 10.
std::string config_with(std::string_view rest, std::string_view model = "h6") {
  return "[[bus]]\nname = \"line1\"\nport = \"/dev/ttyUSB0\"\n[[sensor]]\nname = \"s\"\n"
         "bus = \"line1\"\nmodel = \"" +
         std::string(model) + "\"\naddress = 223\nunit_id = 1\n" + std::string(rest);
}

// A point table of 6 lines: header, name, table, address, type, source.
std::string point(std::string_view name, std::string_view table, int address, std::string_view type,
                  std::string_view source) {
  return "[[point]]\nname = \"" + std::string(name) + "\"\ntable = \"" + std::string(table) +
         "\"\naddress = " + std::to_string(address) + "\ntype = \"" + std::string(type) +
         "\"\nsource = \"" + std::string(source) + "\"\n";
}

ConfigErrors errors_of(const std::string& config_path) {
  auto loaded = load_config_file(config_path, registered_families());
  REQUIRE_FALSE(loaded.has_value());
  return loaded.error();
}

ConfigErrors errors_of_text(const std::string& text) {
  auto loaded = load_config_string(text, "test.toml", registered_families());
  REQUIRE_FALSE(loaded.has_value());
  return loaded.error();
}

void expect_only(const ConfigErrors& errors, const std::string& file, int line,
                 std::string_view key, std::string_view message) {
  INFO(joined(errors));
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].file == file);
  CHECK(errors[0].line == line);
  CHECK(errors[0].key == key);
  CHECK(errors[0].message == message);
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

const fs::path kSource = TILTGATE_SOURCE_DIR;

}  // namespace

TEST_CASE("map files: a sensor's map file is found next to the config file") {
  ScratchDir dir;
  dir.write("maps/plant-a.toml", "extends = \"default\"\n" +
                                     point("grade", "input", 100, "float32", "angle_x") +
                                     "angle_unit = \"percent\"\n");
  const auto config = dir.write("plant.toml", config_with("map = \"maps/plant-a.toml\"\n"));
  auto loaded = load_config_file(config, registered_families());
  INFO((loaded ? std::string() : joined(loaded.error())));
  REQUIRE(loaded.has_value());
  const SensorConfig& s = loaded->sensors[0];
  REQUIRE(s.map.has_value());
  CHECK(s.map_file == (dir.path / "maps/plant-a.toml").string());
  const RegisterMap map = build_map(registered_families(), s.map, s.model);
  REQUIRE(map.find("grade") != nullptr);
  CHECK(map.find("grade")->angle_unit == AngleUnit::percent_grade);
  CHECK(map.find("angle_x") != nullptr);  // kept from the built-in map
}

TEST_CASE("map files: a problem in a map file is reported at its own line") {
  ScratchDir dir;
  const auto map = dir.write("maps/m.toml", point("a", "input", 0, "float32", "angle_x") +
                                                point("b", "input", 1, "uint16", "status"));
  const auto config = dir.write("plant.toml", config_with("map = \"maps/m.toml\"\n"));
  expect_only(errors_of(config), map, 10, "point[1].address",
              "\"b\" at input 1..1 overlaps \"a\" at 0..1");
}

TEST_CASE("map files: a model check names the model, once per file and model") {
  ScratchDir dir;
  const auto map = dir.write("maps/raw.toml", point("raw", "input", 0, "int32", "raw_counts"));
  std::string text = config_with("map = \"maps/raw.toml\"\n");
  text +=
      "[[sensor]]\nname = \"t\"\nbus = \"line1\"\nmodel = \"h6\"\naddress = 224\n"
      "unit_id = 2\nmap = \"maps/raw.toml\"\n";
  expect_only(errors_of(dir.write("plant.toml", text)), map, 6, "point[0].source",
              "model \"h6\" does not offer raw_counts");
}

TEST_CASE("map files: a missing file is reported at the sensor's map key") {
  ScratchDir dir;
  const auto config = dir.write("plant.toml", config_with("map = \"maps/none.toml\"\n"));
  expect_only(errors_of(config), config, 10, "sensor[0].map",
              "\"maps/none.toml\" (" + (dir.path / "maps/none.toml").string() +
                  ") cannot open: No such file or directory");
}

TEST_CASE("map files: a syntax error in a map file is reported in that file") {
  ScratchDir dir;
  const auto map = dir.write("maps/bad.toml", "[[point]\nname = 1\n");
  const auto config = dir.write("plant.toml", config_with("map = \"maps/bad.toml\"\n"));
  const ConfigErrors errors = errors_of(config);
  INFO(joined(errors));
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].file == map);
  CHECK(errors[0].line == 1);
}

TEST_CASE("map files: keys of a point are checked with did-you-mean") {
  ScratchDir dir;
  const auto map =
      dir.write("maps/m.toml", point("a", "input", 0, "float32", "angel_x") + "scael = 2\n");
  const auto config = dir.write("plant.toml", config_with("map = \"maps/m.toml\"\n"));
  const ConfigErrors errors = errors_of(config);
  INFO(joined(errors));
  REQUIRE(errors.size() == 2);
  CHECK(errors[0].to_string() ==
        map + ":6:1: point[0].source: \"angel_x\" is not valid; did you mean \"angle_x\"?");
  CHECK(errors[1].to_string() ==
        map + ":7:1: point[0].scael: unknown key; did you mean \"scale\"?");
}

TEST_CASE("map files: an inline map, with errors at the config file's lines") {
  const std::string inline_map = config_with(
      "[sensor.map]\nextends = \"default\"\nremove = [\"angle_y_cdeg\"]\n"
      "[[sensor.map.point]]\nname = \"grade\"\ntable = \"input\"\naddress = 5\n"
      "type = \"int16\"\nsource = \"angle_x\"\nangle_unit = \"percent\"\n");
  auto loaded = load_config_string(inline_map, "test.toml", registered_families());
  REQUIRE_FALSE(loaded.has_value());
  INFO(joined(loaded.error()));
  REQUIRE(loaded.error().size() == 1);
  CHECK(loaded.error()[0].to_string() ==
        "test.toml:17:1: sensor[0].map.point[0].type: int16 cannot hold angle_x in percent: its "
        "range has no bounds; use a wider type or a smaller scale, or saturate = true to clamp");
  auto fixed = load_config_string(inline_map + "saturate = true\n", "test.toml", registered_families());
  INFO((fixed ? std::string() : joined(fixed.error())));
  REQUIRE(fixed.has_value());
  const RegisterMap map = build_map(registered_families(), fixed->sensors[0].map, "h6");
  CHECK(map.find("grade")->address == 5);
  CHECK(map.find("angle_y_cdeg") == nullptr);
}

TEST_CASE("map files: problems of built-in points are reported at extends") {
  expect_only(errors_of_text(config_with("map = { extends = \"h6\" }\n", "h4360")), "test.toml", 10,
              "sensor[0].map.extends",
              "built-in point \"zero_y\": write: model \"h4360\" does not accept writes of zero_y");
}

TEST_CASE("map files: standby is a source a map file names, as a bit or packed with others") {
  const std::string map_text =
      "[sensor.map]\nextends = \"default\"\n" + point("heard", "discrete", 20, "bool", "standby") +
      "[[sensor.map.point]]\nname = \"flags\"\ntable = \"input\"\naddress = 100\n"
      "type = \"uint16\"\nbits = [\"online\", \"wrong_device\", \"standby\"]\n";
  std::string text = config_with(map_text);
  // point() writes a [[point]] header; inline, it is [[sensor.map.point]].
  text.replace(text.find("[[point]]"), 9, "[[sensor.map.point]]");
  auto loaded = load_config_string(text, "test.toml", registered_families());
  INFO((loaded ? std::string() : joined(loaded.error())));
  REQUIRE(loaded.has_value());
  const RegisterMap map = build_map(registered_families(), loaded->sensors[0].map, "h6");
  CHECK(map.find("heard")->source == ValueSource::standby);
  CHECK(map.find("flags")->bits.back() == ValueSource::standby);
  CHECK(map.find("standby")->address == 8);  // the built-in discrete input, kept
  CHECK(map.validate(registered_families(), "h6").empty());
}

TEST_CASE("map files: remove must name a built-in point, and a map needs points") {
  expect_only(errors_of_text(config_with("map = { extends = \"default\", remove = [\"nope\"] }\n")),
              "test.toml", 10, "sensor[0].map.remove",
              "\"nope\" is not a point of the built-in \"h6\" map");
  expect_only(errors_of_text(config_with("map = { }\n")), "test.toml", 10, "sensor[0].map.point",
              "the map has no points; add [[point]] tables or extends = \"default\"");
  expect_only(errors_of_text(config_with("map = 5\n")), "test.toml", 10, "sensor[0].map",
              "expected a map file name (a string) or an inline map (a table), got an integer");
}

TEST_CASE("map files: the examples load and validate") {
  auto loaded = load_config_file((kSource / "examples/tiltgate-maps.toml").string(), registered_families());
  INFO((loaded ? std::string() : joined(loaded.error())));
  REQUIRE(loaded.has_value());
  REQUIRE(loaded->sensors.size() == 4);
  for (const SensorConfig& s : loaded->sensors) {
    CAPTURE(s.name);
    REQUIRE(s.map.has_value());
    const RegisterMap map = build_map(registered_families(), s.map, s.model);
    CHECK(map.validate(registered_families(), s.model).empty());
  }
  CHECK(loaded->sensors[0].map_file == (kSource / "examples/maps/cdab-floats.toml").string());
  CHECK(loaded->sensors[1].map_file == (kSource / "examples/maps/int16-scaled.toml").string());
  CHECK(loaded->sensors[2].map_file == (kSource / "examples/maps/holding-only.toml").string());
  const RegisterMap holding_only = build_map(registered_families(), loaded->sensors[2].map, "h6");
  CHECK_FALSE(holding_only.has_table(RegisterTable::input));
  CHECK_FALSE(holding_only.has_table(RegisterTable::discrete));
  CHECK(loaded->sensors[3].mounting.invert_x);
  CHECK(loaded->sensors[3].alarms.tilt_high == 8.0);
}

TEST_CASE("docs/default-maps.md is the markdown export of the built-in maps") {
  const fs::path config = kSource / "examples/builtin-maps.toml";
  auto loaded = load_config_file(config.string(), registered_families());
  REQUIRE(loaded.has_value());
  std::vector<RegisterMap> maps;
  maps.reserve(loaded->sensors.size());
  std::vector<UnitMap> units;
  for (const SensorConfig& s : loaded->sensors) {
    maps.push_back(build_map(registered_families(), s.map, s.model));
    units.push_back({s.unit_id, s.name, s.model, &maps.back(), loaded->server.word_order});
  }
  // The page's headings name no port (the demo's is its own): `map` adds ", port 502".
  INFO(
      "docs/default-maps.md is out of date; regenerate it with\n"
      "  build/tiltgate map --format markdown --config examples/builtin-maps.toml "
      "| sed 's/, port [0-9]*$//' > docs/default-maps.md");
  CHECK(read_file(kSource / "docs/default-maps.md") == export_markdown(units));
}

// docs/register-maps.md, "Register-map files": its first TOML block is the annotated map file.
TEST_CASE("the annotated map file of docs/register-maps.md loads") {
  const std::string page = read_file(kSource / "docs/register-maps.md");
  const auto section = page.find("## Register-map files");
  REQUIRE(section != std::string::npos);
  const auto start = page.find("```toml\n", section);
  REQUIRE(start != std::string::npos);
  const auto end = page.find("```\n", start + 8);
  REQUIRE(end != std::string::npos);
  ScratchDir dir;
  dir.write("maps/annotated.toml", page.substr(start + 8, end - start - 8));
  auto loaded =
      load_config_file(dir.write("plant.toml", config_with("map = \"maps/annotated.toml\"\n")), registered_families());
  INFO((loaded ? std::string() : joined(loaded.error())));
  REQUIRE(loaded.has_value());
  const RegisterMap map = build_map(registered_families(), loaded->sensors[0].map, "h6");
  CHECK(map.find("angle_x")->address == 100);
  CHECK(map.find("grade")->nan_value == -32768);
  CHECK(map.find("flags")->bits.size() == 4);
  CHECK(map.find("zero_x_cdeg")->write == WriteTarget::zero_x);
}

// Every problem in one run: a key error (in the config, in the map, or the sensor's model) hides
// no map problem of the points that did read.
namespace {

bool has_error(const ConfigErrors& errors, const std::string& file, int line, std::string_view key,
               std::string_view message) {
  for (const ConfigError& e : errors)
    if (e.file == file && e.line == line && e.key == key &&
        e.message.find(message) != std::string::npos)
      return true;
  return false;
}

// Point "a" float32 at input 0, point "b" at input 1 (overlapping "a"), point "c" with a
// misspelt key (lines 10 and 19 of the text); each point table opens with `header`
// ("[[point]]" or "[[sensor.map.point]]").
std::string overlapping_points_and_a_misspelt_key(std::string_view header) {
  const std::string h(header);
  return h + "\nname = \"a\"\ntable = \"input\"\naddress = 0\ntype = \"float32\"\n" +
         "source = \"angle_x\"\n" + h + "\nname = \"b\"\ntable = \"input\"\naddress = 1\n" +
         "type = \"uint16\"\nsource = \"status\"\n" + h + "\nname = \"c\"\ntable = \"input\"\n" +
         "address = 5\ntype = \"uint16\"\nsource = \"status\"\nscael = 10\n";
}

constexpr std::string_view kOverlap = "\"b\" at input 1..1 overlaps \"a\" at 0..1";

}  // namespace

TEST_CASE("map files: an inline map's problems are reported with every key error, in one run") {
  // Line 10: a misspelt sensor key; 11..29 the points; 30..31 a misspelt [server] key.
  const ConfigErrors errors = errors_of_text(
      config_with("poll_sm = 100\n" + overlapping_points_and_a_misspelt_key("[[sensor.map.point]]") +
                  "[server]\nprot = 502\n"));
  INFO(joined(errors));
  CHECK(has_error(errors, "test.toml", 10, "sensor[0].poll_sm", "unknown key"));
  CHECK(has_error(errors, "test.toml", 20, "sensor[0].map.point[1].address", kOverlap));
  CHECK(has_error(errors, "test.toml", 29, "sensor[0].map.point[2].scael", "unknown key"));
  CHECK(has_error(errors, "test.toml", 31, "server.prot", "unknown key"));
  CHECK(errors.size() == 4);
}

TEST_CASE("map files: a map file's problems are reported with every key error, in one run") {
  ScratchDir dir;
  const auto map = dir.write("maps/m.toml", overlapping_points_and_a_misspelt_key("[[point]]"));
  const auto config =
      dir.write("plant.toml", config_with("poll_sm = 100\nmap = \"maps/m.toml\"\n"));
  const ConfigErrors errors = errors_of(config);
  INFO(joined(errors));
  CHECK(has_error(errors, config, 10, "sensor[0].poll_sm", "unknown key"));
  CHECK(has_error(errors, map, 10, "point[1].address", kOverlap));
  CHECK(has_error(errors, map, 19, "point[2].scael", "unknown key"));
  CHECK(errors.size() == 3);
}

TEST_CASE("map files: a map is checked even when the sensor's model is in error") {
  const ConfigErrors errors = errors_of_text(
      config_with(overlapping_points_and_a_misspelt_key("[[sensor.map.point]]"), "h7"));
  INFO(joined(errors));
  CHECK(has_error(errors, "test.toml", 7, "sensor[0].model", "\"h7\""));
  CHECK(has_error(errors, "test.toml", 19, "sensor[0].map.point[1].address", kOverlap));
  CHECK(has_error(errors, "test.toml", 28, "sensor[0].map.point[2].scael", "unknown key"));
  CHECK(errors.size() == 3);
}

TEST_CASE("map files: a point with a key error adds no false clash") {
  // "c" misses its address, so it holds address 0, where "a" is: no overlap may be reported.
  const ConfigErrors errors = errors_of_text(config_with(
      "[[sensor.map.point]]\nname = \"a\"\ntable = \"input\"\naddress = 0\ntype = \"float32\"\n"
      "source = \"angle_x\"\n[[sensor.map.point]]\nname = \"c\"\ntable = \"input\"\n"
      "type = \"float32\"\nsource = \"angle_y\"\n"));
  INFO(joined(errors));
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].key == "sensor[0].map.point[1].address");
}
