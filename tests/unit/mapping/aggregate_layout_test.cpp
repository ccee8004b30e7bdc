// The aggregate unit's layout ([[aggregate]]): the same points of many sensors back to back,
// sensor i's block at i x the block's size; each point as wide as in the sensors' maps; and
// reads of any range of it, each point read as on the sensor's own unit.
#include <doctest/doctest.h>

#include <cstring>
#include <string>
#include <vector>

#include "mapping/aggregate_layout.h"
#include "mapping/default_maps.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using Words = std::vector<std::uint16_t>;

const std::vector<std::string> kAngles{"angle_x", "angle_y", "status"};

SensorState online_at(SteadyClock::time_point now, double x, double y) {
  SensorState s;
  s.online = true;
  s.identity_known = true;
  Reading r;
  r.angle_x = x;
  r.angle_y = y;
  r.taken = now - 10ms;
  s.reading = r;
  return s;
}

float float_in(const Words& words, std::size_t at) {
  const std::uint32_t bits = std::uint32_t(words.at(at)) << 16 | words.at(at + 1);
  float value = 0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// Three H6 at (1.5, -2.25), (10, 20), (-30.5, 0.25), all read at `now`.
struct ThreeSensors {
  RegisterMap map = default_map(registered_families(), "h6");
  SteadyClock::time_point now = SteadyClock::now();
  std::vector<SensorState> states{online_at(now, 1.5, -2.25), online_at(now, 10, 20),
                                  online_at(now, -30.5, 0.25)};
  std::vector<AggregateMember> members{{"s1", &map}, {"s2", &map}, {"s3", &map}};

  std::vector<AggregateSource> sources(MemberRange range, OfflineRead offline = {}) const {
    std::vector<AggregateSource> out;
    for (std::size_t i = range.first; i < range.last; ++i) {
      SensorView view{states[i], now, 1000ms, {}};
      view.offline = offline;
      view.substitute = 7.5;
      out.push_back({&map, view});
    }
    return out;
  }
  Expected<Words, MapFault> read(const AggregateLayout& layout, std::uint16_t address,
                                 std::uint16_t count, OfflineRead offline = {}) const {
    const MemberRange range = members_in(layout, address, count);
    return read_aggregate(layout, range, sources(range, offline), address, count);
  }
};

}  // namespace

TEST_CASE("aggregate layout: points back to back in the order given, sensor i at i x block") {
  const ThreeSensors plant;
  auto layout = make_aggregate_layout(kAngles, plant.members);
  REQUIRE(layout.has_value());
  CHECK(layout->block_words == 5);  // float32, float32, uint16
  REQUIRE(layout->slots.size() == 3);
  CHECK(layout->slots[0].offset == 0);
  CHECK(layout->slots[1].offset == 2);
  CHECK(layout->slots[2].offset == 4);
  CHECK(layout->slots[2].words == 1);
  CHECK(layout->block_start(0) == 0);
  CHECK(layout->block_start(2) == 10);
  CHECK(layout->end() == 15);
}

TEST_CASE("aggregate layout: int16 angles make a 2-register block, 60 sensors in one request") {
  const RegisterMap map = default_map(registered_families(), "h6");
  std::vector<std::string> names;
  std::vector<AggregateMember> members;
  names.reserve(60);
  for (int i = 0; i < 60; ++i) names.push_back("s" + std::to_string(i));
  for (const std::string& name : names) members.push_back({name, &map});
  auto layout = make_aggregate_layout(std::vector<std::string>{"angle_x_cdeg", "angle_y_cdeg"},
                                      members);
  REQUIRE(layout.has_value());
  CHECK(layout->block_words == 2);
  CHECK(layout->end() == 120);  // within the 125 registers of one FC3/FC4 request
}

TEST_CASE("aggregate layout: a point missing, of another type, or not a register is refused") {
  const RegisterMap h6 = default_map(registered_families(), "h6");
  const RegisterMap other({make_point("angle_x", RegisterTable::input, 0, PointType::int16,
                                      ValueSource::angle_x)});
  const std::vector<AggregateMember> members{{"s1", &h6}, {"s2", &other}};
  auto missing = make_aggregate_layout(std::vector<std::string>{"angle_y"}, members);
  REQUIRE_FALSE(missing.has_value());
  CHECK(missing.error() == "sensor \"s2\": its map has no point \"angle_y\"");
  auto narrower = make_aggregate_layout(std::vector<std::string>{"angle_x"}, members);
  REQUIRE_FALSE(narrower.has_value());
  CHECK(narrower.error() ==
        "sensor \"s2\": point \"angle_x\" is int16 (1 register) here but float32 (2 registers) "
        "in sensor \"s1\"; an aggregate's point must be the same in every sensor's map");
  const std::vector<AggregateMember> one{{"s1", &h6}};
  auto bit = make_aggregate_layout(std::vector<std::string>{"online"}, one);
  REQUIRE_FALSE(bit.has_value());
  CHECK(bit.error() == "sensor \"s1\": point \"online\" is a discrete point, expected an input or "
                       "holding register point");
}

TEST_CASE("aggregate layout: more sensors than a unit's 65536 registers hold are refused") {
  const RegisterMap map = default_map(registered_families(), "h6");
  std::vector<AggregateMember> members(13108, AggregateMember{"s", &map});  // x 5 = 65540
  auto layout = make_aggregate_layout(kAngles, members);
  REQUIRE_FALSE(layout.has_value());
  CHECK(layout.error().find("65540 registers, more than the 65536") != std::string::npos);
  members.pop_back();  // 13107 x 5 = 65535
  CHECK(make_aggregate_layout(kAngles, members).has_value());
}

TEST_CASE("aggregate read: each sensor's values at its block's offset") {
  const ThreeSensors plant;
  const AggregateLayout layout = *make_aggregate_layout(kAngles, plant.members);
  auto words = plant.read(layout, 0, 15);
  REQUIRE(words.has_value());
  CHECK(float_in(*words, 0) == 1.5f);
  CHECK(float_in(*words, 2) == -2.25f);
  CHECK(((*words)[4] & 0x01) == 0x01);  // online
  CHECK(float_in(*words, 5) == 10.0f);
  CHECK(float_in(*words, 7) == 20.0f);
  CHECK(float_in(*words, 10) == -30.5f);
  CHECK(float_in(*words, 12) == 0.25f);
  // Part of the range: the second sensor's Y and status, then the third's X.
  auto middle = plant.read(layout, 7, 5);
  REQUIRE(middle.has_value());
  CHECK(float_in(*middle, 0) == 20.0f);
  CHECK(float_in(*middle, 3) == -30.5f);
}

TEST_CASE("aggregate read: a range past the end or splitting a float is an illegal address") {
  const ThreeSensors plant;
  const AggregateLayout layout = *make_aggregate_layout(kAngles, plant.members);
  CHECK(plant.read(layout, 14, 2).error() == MapFault::illegal_address);  // past the end
  CHECK(plant.read(layout, 15, 1).error() == MapFault::illegal_address);
  CHECK(plant.read(layout, 1, 2).error() == MapFault::illegal_address);   // splits angle_x
  CHECK(plant.read(layout, 5, 1).error() == MapFault::illegal_address);   // half of s2's X
  CHECK(plant.read(layout, 14, 1).has_value());                           // s3's status alone
}

TEST_CASE("aggregate read: an offline sensor reads as its own unit would, by its offline rule") {
  ThreeSensors plant;
  plant.states[1].online = false;
  const AggregateLayout layout = *make_aggregate_layout(kAngles, plant.members);
  // offline = "exception": its angles make the request 0x0B, as on its own unit...
  CHECK(plant.read(layout, 0, 15).error() == MapFault::unavailable);
  // ...but its status still reads (not a measurement), and so do the others' blocks.
  auto status = plant.read(layout, 9, 1);
  REQUIRE(status.has_value());
  CHECK(((*status)[0] & 0x01) == 0);
  CHECK(plant.read(layout, 10, 5).has_value());
  // offline = "substitute": its angles show the substitute, the others their readings.
  auto substituted = plant.read(layout, 0, 15, OfflineRead::substitute);
  REQUIRE(substituted.has_value());
  CHECK(float_in(*substituted, 0) == 1.5f);
  CHECK(float_in(*substituted, 5) == 7.5f);
  CHECK(float_in(*substituted, 7) == 7.5f);
  CHECK(float_in(*substituted, 10) == -30.5f);
}

TEST_CASE("aggregate map: each sensor's points under SENSOR.POINT at their block's place") {
  const ThreeSensors plant;
  const AggregateLayout layout = *make_aggregate_layout(kAngles, plant.members);
  const RegisterMap map = aggregate_register_map(layout, plant.members);
  REQUIRE(map.points().size() == 9);
  REQUIRE(map.find("s3.angle_y") != nullptr);
  CHECK(map.find("s3.angle_y")->address == 12);
  CHECK(map.find("s2.status")->address == 9);
  CHECK(map.find("s1.angle_x")->type == PointType::float32);
  CHECK(map.validate().empty());
}
