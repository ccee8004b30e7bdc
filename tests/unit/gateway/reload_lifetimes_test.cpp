// What a reload does to the bus and router under requests in flight (Gateway::reload, gateway/gateway.cpp):
// a sensor the reload drops stays alive while its poll is on the wire or a client's write to it
// waits for the bus, that write is still carried out and answered, and a retired bus carries
// out its queued writes before it stops. A FakeLine and fake drivers (unit/support/fake_bus.h).
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <algorithm>
#include <optional>

#include "line_scheduling/bus_scheduler.h"
#include "modbus_tcp/modbus_request.h"
#include "gateway/request_router.h"
#include "unit/support/fake_bus.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;

namespace {

ModbusRequest write_filter(std::uint8_t unit, std::uint16_t value) {
  ModbusRequest request;
  request.unit_id = unit;
  request.function = modbus_function::write_single_register;
  request.table = ModbusTable::holding;
  request.is_write = true;
  request.address = 0;  // filter, built-in H6 map
  request.count = 1;
  request.registers = {value};
  return request;
}

bool happened(const BusEvents& events, const std::string& event) {
  return std::find(events.begin(), events.end(), event) != events.end();
}

// Unit 1 "a" and unit 2 "b" on one bus, owned the way the gateway owns them: shared.
struct Bus {
  Bus() {
    for (auto [name, unit] : {std::pair{"a", 1}, std::pair{"b", 2}}) {
      std::shared_ptr<GatewaySensor> sensor =
          fake_sensor(name, std::uint8_t(unit), std::uint32_t(200 + unit), events, 10s);
      scheduler.add(sensor);
      router.add(sensor);
      sensors.push_back(std::move(sensor));
    }
    asio::co_spawn(io, [this]() -> asio::awaitable<void> {
      co_await scheduler.run();
      run_ended = true;
    }, asio::detached);
  }
  ~Bus() {
    scheduler.stop();
    io.restart();
    io.run_for(100ms);
  }
  void send(ModbusRequest request, std::optional<ModbusResponse>& response) {
    asio::co_spawn(
        io,
        [this, request = std::move(request), &response]() -> asio::awaitable<void> {
          response = co_await router.handle(request);
        },
        asio::detached);
  }
  // What a reload does to a sensor it removes or replaces: out of the router and the polls,
  // and the gateway's own reference dropped.
  std::weak_ptr<GatewaySensor> drop(std::size_t index) {
    std::weak_ptr<GatewaySensor> dropped = sensors[index];
    router.clear();
    for (std::size_t i = 0; i < sensors.size(); ++i)
      if (i != index && sensors[i]) router.add(sensors[i]);
    scheduler.remove(*sensors[index]);
    sensors[index].reset();
    return dropped;
  }

  asio::io_context io;
  FakeLine line{io.get_executor()};
  BusScheduler scheduler{io.get_executor(), line, "bus"};
  RequestRouter router{io.get_executor(), RouterOptions{true, WordOrder::big, 3000ms}};
  BusEvents events;
  std::vector<std::shared_ptr<GatewaySensor>> sensors;
  bool run_ended = false;
};

}  // namespace

TEST_CASE("reload: a dropped sensor's queued write is carried out, answered, then it is freed") {
  Bus bus;
  fake_driver(*bus.sensors[1]).write_time = 200ms;  // b's write holds the line
  FakeDriver& a = fake_driver(*bus.sensors[0]);
  REQUIRE(run_until(bus.io, [&] { return happened(bus.events, "a poll end"); }));
  std::optional<ModbusResponse> b_done, a_done;
  std::vector<std::pair<WriteTarget, double>> a_wrote;
  bus.send(write_filter(2, 3), b_done);
  REQUIRE(run_until(bus.io, [&] { return happened(bus.events, "b write"); }));
  bus.send(write_filter(1, 5), a_done);  // queued behind b's
  bus.io.restart();
  bus.io.poll();
  REQUIRE_FALSE(a_done.has_value());

  const std::weak_ptr<GatewaySensor> dropped = bus.drop(0);
  CHECK_FALSE(dropped.expired());  // the request waiting for the bus holds it
  // `a` is freed by the time the answer is seen: what it wrote is copied while it lives (the
  // write's transaction is on the wire).
  REQUIRE(run_until(bus.io, [&] {
    if (!dropped.expired() && happened(bus.events, "a write")) a_wrote = a.writes;
    return a_done.has_value();
  }));
  CHECK(happened(bus.events, "a write end"));
  CHECK_FALSE(a_done->exception.has_value());
  REQUIRE(a_wrote.size() == 1);
  CHECK(a_wrote[0].second == 5);
  CHECK(dropped.expired());  // and freed once answered
  // The unit is no longer served.
  std::optional<ModbusResponse> later;
  bus.send(write_filter(1, 6), later);
  REQUIRE(run_until(bus.io, [&] { return later.has_value(); }));
  CHECK(later->exception == ModbusException::gateway_path_unavailable);
}

TEST_CASE("reload: a sensor dropped while its poll is on the wire finishes it, the rest go on") {
  Bus bus;
  fake_driver(*bus.sensors[0]).poll_time = 200ms;
  REQUIRE(run_until(bus.io, [&] { return happened(bus.events, "a poll"); }));
  const std::weak_ptr<GatewaySensor> dropped = bus.drop(0);
  CHECK_FALSE(dropped.expired());  // the scheduler holds it until its poll ends
  REQUIRE(run_until(bus.io, [&] { return dropped.expired(); }));
  CHECK(happened(bus.events, "a poll end"));
  CHECK(std::count(bus.events.begin(), bus.events.end(), "a poll") == 1);
  // b is still polled (its 10 s period: due once, at start).
  REQUIRE(run_until(bus.io, [&] { return happened(bus.events, "b poll end"); }));
}

TEST_CASE("reload: a retired bus carries out its queued writes, then its loop ends") {
  Bus bus;
  fake_driver(*bus.sensors[0]).write_time = 100ms;
  fake_driver(*bus.sensors[1]).write_time = 100ms;
  REQUIRE(run_until(bus.io, [&] { return happened(bus.events, "b poll end"); }));
  std::optional<ModbusResponse> a_done, b_done;
  bus.send(write_filter(1, 5), a_done);
  bus.send(write_filter(2, 2), b_done);
  REQUIRE(run_until(bus.io, [&] { return happened(bus.events, "a write"); }));
  const std::size_t polls_before = bus.events.size();
  bus.drop(0);
  bus.drop(1);
  bus.scheduler.retire();
  REQUIRE(run_until(bus.io, [&] { return a_done && b_done && bus.run_ended; }));
  CHECK_FALSE(a_done->exception.has_value());
  CHECK_FALSE(b_done->exception.has_value());
  // Nothing but the writes after the retirement: no poll.
  for (std::size_t i = polls_before; i < bus.events.size(); ++i)
    CHECK(bus.events[i].find("poll") == std::string::npos);
}
