// Writes of float points: what is not a number (NaN, infinity) and what is a subnormal (a
// float32 sent with its two words swapped) is refused with illegal_value (0x03), before scale,
// offset and range are applied; zero and ordinary values pass.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "mapping/default_maps.h"
#include "mapping/map_access.h"
#include "mapping/value_codec.h"

using namespace tiltgate;

namespace {

using Words = std::vector<std::uint16_t>;

// A float32 and a float64 point whose range is everything, so only the number check can
// refuse a value (an angle in percent grade has an infinite range, too).
RegisterMap unbounded_float_map() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Point single = holding_point("single", 0, PointType::float32, WriteTarget::zero_x, -inf, inf,
                               "", "");
  Point twice = holding_point("double", 2, PointType::float64, WriteTarget::zero_y, -inf, inf,
                              "", "");
  return RegisterMap({single, twice});
}

Words float_words(PointType type, double value) {
  Words words(type == PointType::float32 ? 2 : 4);
  encode_number(words, type, value, RegisterOrder::abcd, Rounding::nearest, 0.0);
  return words;
}
Words float32_words(float value) { return float_words(PointType::float32, value); }
Words float64_words(double value) { return float_words(PointType::float64, value); }

std::optional<MapFault> fault_of(const RegisterMap& map, std::uint16_t address,
                                 const Words& words) {
  auto plan = plan_register_write(map, WordOrder::big, address, words);
  if (plan) return std::nullopt;
  return plan.error();
}

}  // namespace

TEST_CASE("a float32 write with its words swapped (a subnormal) is refused with 0x03") {
  const auto map = default_map(registered_families(), "h6");  // zero_x: float32 at holding 1, -180..180
  // mbpoll -t 4:float without -B sends 0.75 (3F40 0000) as 0000 3F40: 2.3e-41.
  CHECK(fault_of(map, 1, {0x0000, 0x3F40}) == MapFault::illegal_value);
  CHECK(fault_of(map, 1, {0x3F40, 0x0000}) == std::nullopt);
  CHECK(fault_of(map, 1, float32_words(-std::numeric_limits<float>::denorm_min())) ==
        MapFault::illegal_value);
}

TEST_CASE("float writes of NaN, infinity and subnormals are refused even where the range is open") {
  const auto map = unbounded_float_map();
  constexpr float inf32 = std::numeric_limits<float>::infinity();
  for (float bad : {std::numeric_limits<float>::quiet_NaN(), inf32, -inf32,
                    std::numeric_limits<float>::denorm_min(), 1e-40f}) {
    CAPTURE(bad);
    CHECK(fault_of(map, 0, float32_words(bad)) == MapFault::illegal_value);
  }
  constexpr double inf64 = std::numeric_limits<double>::infinity();
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), inf64, -inf64,
                     std::numeric_limits<double>::denorm_min(), 1e-310}) {
    CAPTURE(bad);
    CHECK(fault_of(map, 2, float64_words(bad)) == MapFault::illegal_value);
  }
}

TEST_CASE("float writes of zero, the smallest normal and ordinary values are accepted") {
  const auto map = unbounded_float_map();
  for (float good : {0.0f, -0.0f, std::numeric_limits<float>::min(), 0.75f, -1e30f}) {
    CAPTURE(good);
    auto plan = plan_register_write(map, WordOrder::big, 0, float32_words(good));
    REQUIRE(plan.has_value());
    CHECK(plan->front().value == double(good));
  }
  for (double good : {0.0, std::numeric_limits<double>::min(), 0.75, 1e300}) {
    CAPTURE(good);
    auto plan = plan_register_write(map, WordOrder::big, 2, float64_words(good));
    REQUIRE(plan.has_value());
    CHECK(plan->front().value == good);
  }
}

TEST_CASE("a write of one point by value (a Sparkplug DCMD) is planned like the Modbus write of "
          "its registers, with the same range check") {
  Point zero = holding_point("zero_x", 10, PointType::int16, WriteTarget::zero_x, -90, 90, "deg",
                             "");
  zero.scale = 100;  // centidegrees, as the built-in maps show an angle
  const RegisterMap map({zero});
  const Point& point = map.points().front();
  auto plan = plan_point_write(map, WordOrder::big, point, 1.25);
  REQUIRE(plan.has_value());
  REQUIRE(plan->size() == 1);
  CHECK((*plan)[0].point == &point);
  CHECK((*plan)[0].value == doctest::Approx(1.25));
  CHECK((*plan)[0].words == Words{125});
  auto same = plan_register_write(map, WordOrder::big, 10, Words{125});
  REQUIRE(same.has_value());
  CHECK((*same)[0].value == (*plan)[0].value);
  // Out of range before encoding: 400 degrees would saturate an int16 into the range otherwise.
  CHECK(plan_point_write(map, WordOrder::big, point, 400).error() == MapFault::illegal_value);
  CHECK(plan_point_write(map, WordOrder::big, point, -90.5).error() == MapFault::illegal_value);
  CHECK(plan_point_write(map, WordOrder::big, point, std::nan("")).error() ==
        MapFault::illegal_value);
}

TEST_CASE("a write by value of a point that is not writable is an illegal address") {
  const RegisterMap map({input_point("angle_x", 0, PointType::int16, ValueSource::angle_x, "deg", "")});
  CHECK(plan_point_write(map, WordOrder::big, map.points().front(), 1).error() ==
        MapFault::illegal_address);
}
