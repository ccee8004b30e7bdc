// What keeps an active gateway from transmitting over another master
// (redundancy/master_guard.h): a request among the bytes received before its own, checksum
// intact, keeps its request back and stands it down; noise and replies do not; a stall of its
// own does; a guard held sends nothing.
#include <doctest/doctest.h>

#include <chrono>
#include <string>
#include <vector>

#include "modbus_rtu/passive_framer.h"
#include "redundancy/master_guard.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using modbus_rtu::test::framed;

namespace {

struct GuardedLine {
  std::vector<std::string> stood_down;
  MasterGuard guard{"line1", modbus_rtu::passive_frame, std::chrono::nanoseconds{572'917},
                    [this](std::string why) { stood_down.push_back(std::move(why)); }};
  GuardedLine() {
    guard.set_stall_limit(1000ms);
    guard.arm(MasterGuard::Clock::now());
  }
};

}  // namespace

TEST_CASE("master guard: nothing received, or noise, lets the request go") {
  GuardedLine g;
  CHECK(g.guard.may_send({}));
  const std::vector<std::uint8_t> noise{0x00, 0xFF, 0x13};
  CHECK(g.guard.may_send(noise));
  CHECK(g.stood_down.empty());
}

TEST_CASE("master guard: another master's request keeps ours back and stands the gateway down") {
  GuardedLine g;
  const auto request = framed("01 04 00 00 00 02");
  CHECK_FALSE(g.guard.may_send(request));
  REQUIRE(g.stood_down.size() == 1);
  CHECK(g.stood_down[0].find("another master's request") != std::string::npos);
  CHECK(g.guard.held());
  CHECK_FALSE(g.guard.may_send({}));  // held: nothing more until armed again
  CHECK(g.stood_down.size() == 1);
}

TEST_CASE("master guard: a request with a broken CRC is noise, not a master") {
  GuardedLine g;
  auto request = framed("01 04 00 00 00 02");
  request.back() ^= 0x55;
  CHECK(g.guard.may_send(request));
  CHECK(g.stood_down.empty());
}

TEST_CASE("master guard: a gateway held up past the stall limit stands down before it sends") {
  GuardedLine g;
  g.guard.alive(MasterGuard::Clock::now() - 2s);
  CHECK_FALSE(g.guard.may_send({}));
  REQUIRE(g.stood_down.size() == 1);
  CHECK(g.stood_down[0].find("held up") != std::string::npos);
}
