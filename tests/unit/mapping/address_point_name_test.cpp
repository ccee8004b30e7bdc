// The common block's address points are named after the setting they show and write,
// bus_address (mapping/common_block.h), and maps written for their former name, rs485_address,
// keep working: a removal, a point put in a built-in one's place and a look-up by name (an
// aggregate's points) find the new name.
#include <doctest/doctest.h>

#include "mapping/common_block.h"
#include "mapping/default_maps.h"
#include "mapping/map_definition.h"

using namespace tiltgate;

namespace {

std::size_t count_named(const RegisterMap& map, std::string_view name) {
  std::size_t n = 0;
  for (const Point& p : map.points()) n += p.name == name;
  return n;
}

}  // namespace

TEST_CASE("the built-in address points are named bus_address, as the setting they write") {
  for (std::string_view model : {"h6", "h4360", "dyna"}) {
    INFO(model);
    const RegisterMap map = default_map(registered_families(), model);
    CHECK(count_named(map, "bus_address") == 2);  // input 14 and holding 7
    CHECK(count_named(map, "rs485_address") == 0);
    const Point* holding = map.find("bus_address");
    REQUIRE(holding != nullptr);
    const auto writes = map.overlapping(RegisterTable::holding, 7, 1);
    REQUIRE(writes.size() == 1);
    CHECK(writes.front().name == "bus_address");
    CHECK(writes.front().write == WriteTarget::bus_address);
  }
}

TEST_CASE("a map naming rs485_address still finds, removes and replaces the address points") {
  const RegisterMap builtin = default_map(registered_families(), "h6");
  CHECK(builtin.find("rs485_address") == builtin.find("bus_address"));
  CHECK(builtin.find("rs486_address") == nullptr);

  MapDefinition removing;
  removing.extends = "h6";
  removing.remove = {"rs485_address"};
  const RegisterMap removed = build_map(registered_families(), removing, "h6");
  CHECK(count_named(removed, "bus_address") == 0);
  CHECK(removed.validate(registered_families(), "h6").empty());

  MapDefinition replacing;
  replacing.extends = "h6";
  Point own = holding_point("rs485_address", 7, PointType::uint16, WriteTarget::bus_address, 1,
                            250, "", "Set Address, 1..250 on this plant");
  replacing.points = {own};
  const RegisterMap replaced = build_map(registered_families(), replacing, "h6");
  CHECK(replaced.validate(registered_families(), "h6").empty());
  const auto writes = replaced.overlapping(RegisterTable::holding, 7, 1);
  REQUIRE(writes.size() == 1);
  CHECK(writes.front().name == "rs485_address");
  CHECK(writes.front().max == 250);
  CHECK(count_named(replaced, "bus_address") == 1);  // the input register stays
}

TEST_CASE("names_point: the same name, or the address point's former one") {
  CHECK(names_point("filter", "filter"));
  CHECK(names_point("rs485_address", "bus_address"));
  CHECK_FALSE(names_point("bus_address", "rs485_address"));
  CHECK_FALSE(names_point("rs485_address", "filter"));
}
