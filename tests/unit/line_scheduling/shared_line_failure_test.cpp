// A bus whose choice of the next turn fails (line_scheduling/shared_line.h): the failure reaches the
// line's own loop, never the claimant that happened to ask; it is logged at error and counted,
// every write, forwarded request and command waiting is refused (answered, not left waiting),
// and turns are given again after the pause, the pollers keeping their places. And a sensor
// whose poll throws (line_scheduling/bus_scheduler.h) is logged, counted and polled again, its
// neighbours untouched. The failures come from the fake driver (unit/support/fake_bus.h).
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <optional>
#include <stdexcept>
#include <string>

#include "line_scheduling/bus_scheduler.h"
#include "line_scheduling/line_claimant.h"
#include "line_scheduling/shared_line.h"
#include "sim/support/captured_log.h"
#include "unit/support/fake_bus.h"
#include "unit/support/scheduler_bench.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;

namespace {

bool logged(const CapturedLog& log, const std::string& text) {
  for (const std::string& line : log.lines())
    if (line.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE("a bus whose choice of turn fails logs it, refuses the waiting write and gives turns again") {
  CapturedLog log(spdlog::level::warn);
  asio::io_context io;
  FakeLine line{io.get_executor()};
  SharedLine shared{io.get_executor(), line, "line1"};
  BusEvents events;
  auto healthy = fake_sensor("a", 1, 1, events);
  asio::co_spawn(io, shared.run(), asio::detached);

  // A sensor's poller, due every 10 ms.
  int polls = 0;
  bool stop = false;
  LineClaimant poller(shared, TurnKind::poll, healthy.get(), std::nullopt);
  asio::co_spawn(io, [&]() -> asio::awaitable<void> {
    while (!stop) {
      if (co_await poller.wait_turn(SteadyClock::now() + 10ms) != TurnGrant::granted) co_return;
      LineRequest request;
      request.bytes = {1};
      request.timeout = 2ms;
      co_await poller.transact(request);
      poller.finish();
      ++polls;
    }
  }, asio::detached);
  // A write waiting for a turn not due for a long time: the failure must answer it.
  std::optional<TurnGrant> write_grant;
  LineClaimant write(shared, TurnKind::write, nullptr, SteadyClock::now() + 30s);
  const auto queued = SteadyClock::now();
  asio::co_spawn(io, [&]() -> asio::awaitable<void> {
    write_grant = co_await write.wait_turn(SteadyClock::now() + 20s);
  }, asio::detached);
  REQUIRE(run_until(io, [&] { return polls >= 3; }));
  // The next look at the sensor while choosing a turn throws, once.
  int throws = 1;
  fake_driver(*healthy).on_state = [&] {
    if (throws-- > 0) throw std::runtime_error("a fault while choosing");
  };

  REQUIRE(run_until(io, [&] { return write_grant.has_value(); }));
  CHECK(*write_grant == TurnGrant::refused);
  CHECK(SteadyClock::now() - queued < 10s);
  CHECK(shared.restarts() == 1);
  CHECK(logged(log, "error line1: choosing the line's next turn failed: a fault while choosing"));
  // Turns again after the pause: the poller kept its place and goes on.
  const int before = polls;
  CHECK(run_until(io, [&] { return polls >= before + 5; }));
  CHECK(line.most_at_once == 1);
  stop = true;
  shared.stop();
  io.restart();
  io.run_for(100ms);
}

TEST_CASE("a sensor whose poll throws is logged at error, counted and polled again, and its neighbour goes on") {
  CapturedLog log(spdlog::level::warn);
  SchedulerBench bus;
  auto& a = fake_driver(bus.add("a", 1, 10ms));
  auto& b = fake_driver(bus.add("b", 2, 10ms));
  a.on_poll = [&] {
    if (a.polls == 2) throw std::runtime_error("a driver fault");
  };
  bus.start();
  REQUIRE(run_until(bus.io, [&] { return a.polls >= 5; }));
  CHECK(b.polls > a.polls);  // polled on while a waited out its pause
  CHECK(bus.scheduler.stats().restarts == 1);
  CHECK(bus.scheduler.stats().poll_failures == 1);
  CHECK(logged(log, "error bus: polling sensor \"a\" failed: a driver fault; polled again in 1 s"));
}
