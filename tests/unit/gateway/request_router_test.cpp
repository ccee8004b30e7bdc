// RequestRouter in front of a BusScheduler with a fake line and fake drivers
// (unit/support/fake_bus.h): writes refused before they reach a driver (writes disabled, an
// address another sensor on the bus has) and the Modbus exception each gets.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
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

constexpr std::uint16_t kFilterRegister = 0;   // built-in H6 map
constexpr std::uint16_t kAddressRegister = 7;  // bus_address

ModbusRequest write_register(std::uint8_t unit, std::uint16_t address, std::uint16_t value) {
  ModbusRequest request;
  request.unit_id = unit;
  request.function = modbus_function::write_single_register;
  request.table = ModbusTable::holding;
  request.is_write = true;
  request.address = address;
  request.count = 1;
  request.registers = {value};
  return request;
}

// Two fake H6 on one bus: unit 1 "left" at 223, unit 2 "right" at 224.
struct Gateway {
  explicit Gateway(bool writes) : router(io.get_executor(), RouterOptions{writes, WordOrder::big, 3000ms}) {
    for (auto [name, address] : {std::pair{"left", 223}, std::pair{"right", 224}}) {
      sensors.push_back(
          fake_sensor(name, std::uint8_t(sensors.size() + 1), std::uint32_t(address), events));
      scheduler.add(*sensors.back());
      router.add(*sensors.back());
    }
  }
  ~Gateway() {
    scheduler.stop();
    io.restart();
    io.run_for(100ms);
  }
  void start() { asio::co_spawn(io, scheduler.run(), asio::detached); }
  // Hands the request to the router from its own coroutine, like a connection.
  void send(ModbusRequest request, std::optional<ModbusResponse>& response) {
    asio::co_spawn(
        io,
        [this, request = std::move(request), &response]() -> asio::awaitable<void> {
          response = co_await router.handle(request);
        },
        asio::detached);
  }
  ModbusResponse handle(ModbusRequest request) {
    std::optional<ModbusResponse> response;
    send(std::move(request), response);
    REQUIRE(run_until(io, [&] { return response.has_value(); }));
    return *response;
  }
  FakeDriver& driver(int unit) { return fake_driver(*sensors.at(std::size_t(unit - 1))); }

  asio::io_context io;
  FakeLine line{io.get_executor()};
  BusScheduler scheduler{io.get_executor(), line, "bus"};
  RequestRouter router{io.get_executor(), RouterOptions{}};
  BusEvents events;
  std::vector<std::unique_ptr<GatewaySensor>> sensors;
};

}  // namespace

TEST_CASE("writes disabled: every write is 0x01 and no driver sees it") {
  Gateway gateway(/*writes=*/false);
  gateway.start();
  const auto response = gateway.handle(write_register(1, kFilterRegister, 3));
  CHECK(response.exception == ModbusException::illegal_function);
  CHECK(gateway.driver(1).checks == 0);
  CHECK(gateway.driver(1).writes.empty());
  CHECK(gateway.scheduler.stats().writes == 0);
}

TEST_CASE("writes enabled: a holding write reaches the driver and reads back") {
  Gateway gateway(/*writes=*/true);
  gateway.start();
  const auto response = gateway.handle(write_register(1, kFilterRegister, 3));
  CHECK_FALSE(response.exception.has_value());
  REQUIRE(gateway.driver(1).writes.size() == 1);
  CHECK(gateway.driver(1).writes[0] == std::pair{WriteTarget::filter, 3.0});
  CHECK(gateway.sensors[0]->written[kFilterRegister] == 3);
}

TEST_CASE("an address another sensor on the bus has is refused with 0x03 before anything is sent") {
  Gateway gateway(/*writes=*/true);
  // The bus loop is not running yet: the answer must come without it (a write that reached
  // the queue would wait for its deadline and be answered busy).
  const auto response = gateway.handle(write_register(2, kAddressRegister, 223));
  CHECK(response.exception == ModbusException::illegal_value);
  CHECK(gateway.line.stats().attempts == 0);
  CHECK(gateway.driver(2).writes.empty());
  CHECK(gateway.driver(2).state().bus_address == 224);
  // Its own address, or a free one, is fine.
  gateway.start();
  CHECK_FALSE(gateway.handle(write_register(2, kAddressRegister, 224)).exception.has_value());
  CHECK_FALSE(gateway.handle(write_register(2, kAddressRegister, 225)).exception.has_value());
  CHECK(gateway.driver(2).state().bus_address == 225);
}

TEST_CASE("two queued address writes to the same address: the second is refused with 0x03") {
  Gateway gateway(/*writes=*/true);
  std::optional<ModbusResponse> first, second;
  // Both are queued before either runs, so both pass the check made when they are queued.
  gateway.send(write_register(2, kAddressRegister, 300), first);
  gateway.send(write_register(1, kAddressRegister, 300), second);
  gateway.start();
  REQUIRE(run_until(gateway.io, [&] { return first.has_value() && second.has_value(); }));
  CHECK_FALSE(first->exception.has_value());
  CHECK(second->exception == ModbusException::illegal_value);
  CHECK(gateway.driver(1).writes.empty());
  CHECK(gateway.driver(1).state().bus_address == 223);
  CHECK(gateway.driver(2).state().bus_address == 300);
}
