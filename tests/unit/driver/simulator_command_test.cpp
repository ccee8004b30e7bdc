#include "driver/simulator_command.h"

#include <doctest/doctest.h>

using tiltgate::parse_simulator_command;

TEST_CASE("a simulator command is a verb, an address and numbers") {
  const auto parsed = parse_simulator_command("  angle 223\t12.5 -3.25e0  ");
  REQUIRE(parsed.has_value());
  CHECK(parsed->verb == "angle");
  CHECK(parsed->address == 223);
  REQUIRE(parsed->values.size() == 2);
  CHECK(parsed->values[0] == 12.5);
  CHECK(parsed->values[1] == -3.25);
  CHECK(parse_simulator_command("counts 5")->values.empty());
}

TEST_CASE("a simulator command that is not one says which word is wrong") {
  CHECK(parse_simulator_command("").error() == "empty command");
  CHECK(parse_simulator_command("   ").error() == "empty command");
  CHECK(parse_simulator_command("angle").error() == "\"angle\" needs a sensor address");
  CHECK(parse_simulator_command("angle -1 2").error() == "\"-1\" is not a sensor address");
  CHECK(parse_simulator_command("angle 1x 2").error() == "\"1x\" is not a sensor address");
  CHECK(parse_simulator_command("angle 1 2,5").error() == "\"2,5\" is not a number");
  CHECK(parse_simulator_command("angle 1 nan").error() == "\"nan\" is not a number");
  CHECK(parse_simulator_command("angle 1 inf").error() == "\"inf\" is not a number");
}
