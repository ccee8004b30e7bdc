// The bus page's hint (gateway/line_hint.h): one plain sentence where the pattern is clear.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "gateway/line_hint.h"

using namespace tiltgate;

namespace {

SensorStatus sensor(std::string name, std::uint32_t address, std::uint64_t checksum,
                    std::uint64_t timeouts) {
  SensorStatus s;
  s.name = std::move(name);
  s.bus = "line1";
  s.address = address;
  FailureCounts recent;
  recent.checksum_errors = checksum;
  recent.timeouts = timeouts;
  s.recent_failures = recent;
  return s;
}

BusStatus bus(std::string port = "/dev/ttyUSB0") {
  BusStatus b;
  b.name = "line1";
  b.port = std::move(port);
  return b;
}

}  // namespace

TEST_CASE("checksum errors on every device point at the line itself") {
  const auto hint = line_hint(bus(), {sensor("boom", 11, 3, 0), sensor("jib", 12, 1, 0)});
  REQUIRE(hint);
  CHECK(hint->find("every device") != std::string::npos);
  CHECK(hint->find("baud rate") != std::string::npos);
  CHECK(hint->find("termination") != std::string::npos);
  CHECK(hint->find("bias") != std::string::npos);
}

TEST_CASE("checksum errors on one device point at its drop or its address") {
  const auto hint =
      line_hint(bus(), {sensor("boom", 11, 0, 0), sensor("jib", 12, 4, 0), sensor("mast", 13, 0, 0)});
  REQUIRE(hint);
  CHECK(*hint == "Checksum errors on jib only: check its drop cable, and that no second device "
                 "answers at its address 12.");
}

TEST_CASE("time-outs on every device behind a device server that reconnected: its packing delay") {
  BusStatus served = bus("tcp://10.0.0.9:4001");
  const std::vector<SensorStatus> silent{sensor("boom", 11, 0, 2), sensor("jib", 12, 0, 5)};
  CHECK_FALSE(line_hint(served, silent).has_value());  // never reconnected: not that
  served.reopens = 1;
  const auto hint = line_hint(served, silent);
  REQUIRE(hint);
  CHECK(hint->find("packing delay") != std::string::npos);
  CHECK_FALSE(line_hint(bus(), silent).has_value());  // a local tty: no device server to blame
}

TEST_CASE("one silent device among answering ones: that device") {
  const auto hint = line_hint(bus(), {sensor("boom", 11, 0, 0), sensor("jib", 12, 0, 7)});
  REQUIRE(hint);
  CHECK(hint->starts_with("jib does not answer"));
  CHECK(hint->find("(12)") != std::string::npos);
}

TEST_CASE("no hint where nothing failed, the pattern is mixed, or the sensors are another bus's") {
  CHECK_FALSE(line_hint(bus(), {sensor("boom", 11, 0, 0), sensor("jib", 12, 0, 0)}).has_value());
  CHECK_FALSE(line_hint(bus(), {sensor("boom", 11, 0, 2), sensor("jib", 12, 0, 3),
                                sensor("mast", 13, 0, 0)})
                  .has_value());
  SensorStatus other = sensor("far", 5, 9, 9);
  other.bus = "line2";
  CHECK_FALSE(line_hint(bus(), {other}).has_value());
}

TEST_CASE("until the recent window is counted, the counts since start say it") {
  SensorStatus boom = sensor("boom", 11, 0, 0);
  boom.recent_failures.reset();
  boom.checksum_errors = 2;
  const auto hint = line_hint(bus(), {boom, sensor("jib", 12, 0, 0)});
  REQUIRE(hint);
  CHECK(hint->starts_with("Checksum errors on boom only"));
}
