// Each check a register map must pass, one mistake at a time: the problem names the point, the
// key it is about and what is wrong.
#include "mapping/map_validation.h"

#include <doctest/doctest.h>

#include <string>

#include "mapping/default_maps.h"
#include "mapping/map_definition.h"
#include "mapping/model_capabilities.h"

using namespace tiltgate;

namespace {

Point point(std::string name, RegisterTable table, std::uint16_t address, PointType type,
            ValueSource source) {
  return make_point(std::move(name), table, address, type, source);
}

Point angle_int16(double scale) {
  Point p = point("x", RegisterTable::input, 0, PointType::int16, ValueSource::angle_x);
  p.scale = scale;
  return p;
}

Point writable(WriteTarget target) {
  Point p = point("w", RegisterTable::holding, 0, PointType::uint16, ValueSource::written);
  p.write = target;
  p.min = 0;
  p.max = 10;
  return p;
}

std::vector<MapProblem> problems_of(const std::vector<Point>& points, std::string_view model) {
  return check_points(points, registered_families(), model);
}

// The one problem of `points` for an h6: its key and message.
MapProblem only_problem(const std::vector<Point>& points, std::string_view model = "h6") {
  const auto problems = check_points(points, registered_families(), model);
  std::string all;
  for (const auto& p : problems) all += p.key + ": " + p.message + "\n";
  INFO(all);
  REQUIRE(problems.size() == 1);
  return problems[0];
}

void expect(const std::vector<Point>& points, std::string_view key, std::string_view message,
            std::string_view model = "h6") {
  const MapProblem problem = only_problem(points, model);
  CHECK(problem.key == key);
  CHECK(problem.message == message);
}

}  // namespace

TEST_CASE("the built-in maps pass every check, also against their model") {
  for (std::string_view model : models_with_default_maps(registered_families())) {
    CAPTURE(model);
    CHECK(default_map(registered_families(), model).validate(registered_families(), model).empty());
  }
}

TEST_CASE("overlapping points are reported once, naming both") {
  const auto a = point("a", RegisterTable::input, 0, PointType::float32, ValueSource::angle_x);
  const auto b = point("b", RegisterTable::input, 1, PointType::uint16, ValueSource::status);
  const MapProblem problem = only_problem({a, b});
  CHECK(problem.key == "address");
  CHECK(problem.point == 1);
  CHECK(problem.other == 0);
  CHECK(problem.message == "\"b\" at input 1..1 overlaps \"a\" at 0..1");
  const auto c = point("c", RegisterTable::holding, 1, PointType::uint16, ValueSource::status);
  CHECK(problems_of({a, c}, "h6").empty());  // another table
}

TEST_CASE("a point must fit its table and the address space") {
  expect({point("p", RegisterTable::coil, 0, PointType::uint16, ValueSource::status)}, "type",
         "uint16 does not fit the coil table: bool points go in coil or discrete, numbers and "
         "strings in input or holding");
  expect({point("p", RegisterTable::input, 0, PointType::boolean, ValueSource::online)}, "type",
         "bool does not fit the input table: bool points go in coil or discrete, numbers and "
         "strings in input or holding");
  expect({point("p", RegisterTable::input, 65535, PointType::float32, ValueSource::angle_x)},
         "address", "2 register(s) from 65535 end past the last address 65535");
}

TEST_CASE("a type that cannot hold its scaled range is an error unless it saturates") {
  CHECK(problems_of({angle_int16(100)}, "h6").empty());  // +-18000 fits
  expect({angle_int16(1000)}, "scale",
         "int16 cannot hold angle_x in deg: -180..180 * 1000 + 0 = -180000..180000 is "
         "beyond -32768..32767; use a wider type or a smaller scale, or saturate = true to clamp");
  Point clamped = angle_int16(1000);
  clamped.saturate = true;
  CHECK(problems_of({clamped}, "h6").empty());
  Point counters = point("n", RegisterTable::input, 0, PointType::uint16, ValueSource::polls_ok);
  expect({counters}, "type",
         "uint16 cannot hold polls_ok: 0..4294967295 is beyond 0..65535; use a wider type or a "
         "smaller scale, or saturate = true to clamp");
  Point mrad = angle_int16(1);
  mrad.angle_unit = AngleUnit::milliradians;  // +-3141.6 fits
  CHECK(problems_of({mrad}, "h6").empty());
}

TEST_CASE("percent grade has no bounds, so an integer point must saturate") {
  Point grade = angle_int16(10);
  grade.angle_unit = AngleUnit::percent_grade;
  expect({grade}, "type",
         "int16 cannot hold angle_x in percent: its range has no bounds; use a wider type or a "
         "smaller scale, or saturate = true to clamp");
  grade.type = PointType::float32;
  CHECK(problems_of({grade}, "h6").empty());
}

TEST_CASE("a writable point must show what was written or the setting, in a holding register") {
  Point on_angle = writable(WriteTarget::filter);
  on_angle.source = ValueSource::angle_x;
  on_angle.type = PointType::float32;
  expect({on_angle}, "write",
         "a writable point shows the value written to it (written) or the sensor's (setting), "
         "but its source is the read-only angle_x; leave source out");
  Point read_back = writable(WriteTarget::filter);
  read_back.source = ValueSource::setting;
  CHECK(problems_of({read_back}, "h6").empty());
  Point in_input = writable(WriteTarget::filter);
  in_input.table = RegisterTable::input;
  expect({in_input}, "write",
         "writes are served on holding registers only, not in the input table");
  Point backwards = writable(WriteTarget::filter);
  backwards.min = 5;
  backwards.max = 1;
  expect({backwards}, "min", "min 5 is greater than max 1");
  expect({point("p", RegisterTable::holding, 0, PointType::uint16, ValueSource::written)}, "source",
         "written shows the last value written through the gateway; it needs a write = \"...\" "
         "setting");
}

TEST_CASE("sources and settings the model does not have are errors") {
  expect({point("raw", RegisterTable::input, 0, PointType::int32, ValueSource::raw_counts)},
         "source", "model \"h6\" does not offer raw_counts");
  expect({writable(WriteTarget::zero_y)}, "write",
         "model \"h4360\" does not accept writes of zero_y", "h4360");
  // angle_y of a single-axis sensor reads NaN, as in the built-in map.
  CHECK(problems_of({point("y", RegisterTable::input, 0, PointType::float32, ValueSource::angle_y)},
                    "h4360")
            .empty());
  CHECK(model_offers(registered_families(), "h4360", ValueSource::angle_y));
  CHECK_FALSE(model_accepts(registered_families(), "no-such-model", WriteTarget::filter));
}

TEST_CASE("bool points need one bit, strings need text, bits need integers") {
  expect({point("p", RegisterTable::discrete, 0, PointType::boolean, ValueSource::angle_x)},
         "source",
         "angle_x is not one bit: a bool point shows a one-bit source (online, stale, "
         "alarm_x_high, ...) or bit = N of an integer source");
  Point bit_of_angle =
      point("p", RegisterTable::discrete, 0, PointType::boolean, ValueSource::angle_x);
  bit_of_angle.bit = 2;
  expect({bit_of_angle}, "bit", "angle_x is not an integer, so it has no bits to pick");
  Point text = point("p", RegisterTable::input, 0, PointType::string, ValueSource::status);
  text.chars = 4;
  expect({text}, "source", "status is a number; a string shows serial or firmware");
  expect({point("p", RegisterTable::input, 0, PointType::uint16, ValueSource::serial)}, "source",
         "serial is text; it needs type = \"string\"");
  Point packed = point("p", RegisterTable::input, 0, PointType::float32, ValueSource::bits);
  expect({packed}, "bits",
         "packs bits into an integer register; float32 is not one (expected uint16, int16, "
         "uint32 or int32)");
  packed.type = PointType::uint16;
  packed.bits.assign(17, ValueSource::online);
  expect({packed}, "bits", "17 bits do not fit a uint16, expected at most 16");
  packed.bits = {ValueSource::status};
  expect({packed}, "bits",
         "status is not one bit, expected a one-bit source such as online or alarm_x_high");
}

TEST_CASE("encoding keys that do not apply, and unusable numbers") {
  Point text = point("p", RegisterTable::input, 0, PointType::string, ValueSource::serial);
  text.chars = 10;
  text.order = RegisterOrder::cdab;
  expect({text}, "word_order", "applies to numeric register types only, not string");
  Point zero = angle_int16(0);
  expect({zero}, "scale",
         "0 is not usable, expected a finite number other than 0 (writes divide by it)");
  Point status = point("s", RegisterTable::input, 0, PointType::uint16, ValueSource::status);
  status.angle_unit = AngleUnit::milliradians;
  expect({status}, "angle_unit", "applies to angle_x, angle_y and tilt only, not status");
  Point sentinel = angle_int16(100);
  sentinel.nan_value = 40000;
  expect({sentinel}, "nan_value", "40000 does not fit int16, expected -32768..32767");
}

TEST_CASE("a name is used once per table") {
  const auto a = point("same", RegisterTable::input, 0, PointType::uint16, ValueSource::status);
  const auto b = point("same", RegisterTable::input, 1, PointType::uint16, ValueSource::age_ms);
  expect({a, b}, "name", "\"same\" is used twice in the input table");
}

TEST_CASE("a map extending a profile keeps its points, replaces by name and removes") {
  MapDefinition definition;
  definition.extends = "default";
  definition.remove = {"angle_y_cdeg"};
  Point moved =
      point("angle_x", RegisterTable::input, 100, PointType::float32, ValueSource::angle_x);
  definition.points = {moved};
  const RegisterMap map = build_map(registered_families(), definition, "h6");
  REQUIRE(map.find("angle_x") != nullptr);
  CHECK(map.find("angle_x")->address == 100);
  CHECK(map.find("angle_y_cdeg") == nullptr);
  CHECK(map.find("status") != nullptr);
  CHECK(map.validate(registered_families(), "h6").empty());
  CHECK(build_map(registered_families(), std::nullopt, "h6").points().size() == default_map(registered_families(), "h6").points().size());
}
