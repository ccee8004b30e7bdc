// The aggregate unit behind the router: FC3 and FC4 read the same registers from the sensors'
// caches, writes and bit reads are refused, and the reply is built in one call that cannot
// suspend, so no poll lands between two sensors of one reply.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <optional>
#include <type_traits>

#include "modbus_tcp/modbus_request.h"
#include "gateway/request_router.h"
#include "unit/support/fake_bus.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;

namespace {

ModbusRequest aggregate_read(std::uint8_t function, ModbusTable table, std::uint16_t address,
                             std::uint16_t count) {
  ModbusRequest request;
  request.unit_id = 200;
  request.function = function;
  request.table = table;
  request.address = address;
  request.count = count;
  return request;
}

// Three fake H6 "s1".."s3" (units 1..3), offline: their angles read the substitute 1.5,
// 2.5, 3.5; an aggregate of their angle_x_cdeg and status on unit 200.
struct AggregatePlant {
  AggregatePlant() : router(io.get_executor(), RouterOptions{true, WordOrder::big, 3000ms}) {
    for (int i = 1; i <= 3; ++i) {
      auto sensor = fake_sensor("s" + std::to_string(i), std::uint8_t(i), std::uint32_t(i), events);
      sensor->config.offline = OfflineRead::substitute;
      sensor->config.substitute = 0.5 + i;
      sensors.push_back(std::shared_ptr<GatewaySensor>(std::move(sensor)));
      sensors.back()->publish();  // as its bus would when it takes it up
      router.add(sensors.back());
    }
    AggregateConfig config;
    config.unit_id = 200;
    config.points = {"angle_x_cdeg", "status"};
    config.sensors = {"s1", "s2", "s3"};
    auto made = make_gateway_aggregate(config, sensors);
    REQUIRE(made.has_value());
    router.add(*made);
  }
  ModbusResponse handle(const ModbusRequest& request) {
    std::optional<ModbusResponse> response;
    asio::co_spawn(
        io, [&]() -> asio::awaitable<void> { response = co_await router.handle(request); },
        asio::detached);
    io.restart();
    io.run();
    REQUIRE(response.has_value());
    return *response;
  }

  BusEvents events;
  asio::io_context io;
  std::vector<std::shared_ptr<GatewaySensor>> sensors;
  RequestRouter router{io.get_executor(), RouterOptions{}};
};

}  // namespace

TEST_CASE("aggregate unit: FC4 and FC3 read each sensor's block, the same registers") {
  AggregatePlant plant;
  const ModbusResponse input =
      plant.handle(aggregate_read(modbus_function::read_input_registers, ModbusTable::input, 0, 6));
  REQUIRE_FALSE(input.exception.has_value());
  // Substitutes show as is (no scale): 1.5 -> 2 (rounded), 2.5 -> 3, 3.5 -> 4.
  CHECK(input.registers.size() == 6);
  CHECK(input.registers[0] == 2);
  CHECK(input.registers[2] == 3);
  CHECK(input.registers[4] == 4);
  CHECK((input.registers[1] & status_bit::online) == 0);
  const ModbusResponse holding = plant.handle(
      aggregate_read(modbus_function::read_holding_registers, ModbusTable::holding, 0, 6));
  REQUIRE_FALSE(holding.exception.has_value());
  CHECK(holding.registers == input.registers);
  // The sensors' own units still answer as before.
  ModbusRequest own = aggregate_read(modbus_function::read_input_registers, ModbusTable::input, 6, 1);
  own.unit_id = 2;
  CHECK_FALSE(plant.handle(own).exception.has_value());
}

TEST_CASE("aggregate unit: writes, bit reads and device identification are illegal functions") {
  AggregatePlant plant;
  ModbusRequest write =
      aggregate_read(modbus_function::write_single_register, ModbusTable::holding, 0, 1);
  write.is_write = true;
  write.registers = {7};
  CHECK(plant.handle(write).exception == ModbusException::illegal_function);
  CHECK(fake_driver(*plant.sensors[0]).writes.empty());
  CHECK(plant.handle(aggregate_read(modbus_function::read_discrete_inputs, ModbusTable::discrete,
                                    0, 1))
            .exception == ModbusException::illegal_function);
  ModbusRequest identify = aggregate_read(modbus_function::encapsulated_interface,
                                          ModbusTable::holding, 0, 0);
  CHECK(plant.handle(identify).exception == ModbusException::illegal_function);
  // A range past the last block.
  CHECK(plant.handle(aggregate_read(modbus_function::read_input_registers, ModbusTable::input, 5,
                                    2))
            .exception == ModbusException::illegal_address);
}

TEST_CASE("aggregate unit: the reply is built in one call that cannot suspend") {
  // A plain function, not an awaitable: nothing (no poll) can run between two sensors of one
  // reply, and every sensor is read at the one `now` it is given.
  static_assert(std::is_same_v<decltype(read_aggregate_unit(
                                   std::declval<const GatewayAggregate&>(),
                                   std::declval<const ModbusRequest&>(), WordOrder::big,
                                   SteadyClock::now())),
                               ModbusResponse>);
  AggregatePlant plant;
  // One instant for all: a `now` at which every reading is stale reads every block as stale,
  // whatever the clock did meanwhile.
  for (auto& sensor : plant.sensors) sensor->config.offline = OfflineRead::exception;
  const auto aggregate = make_gateway_aggregate(
      AggregateConfig{200, {"status"}, {"s1", "s2", "s3"}, "", 0}, plant.sensors);
  REQUIRE(aggregate.has_value());
  const ModbusResponse reply = read_aggregate_unit(
      **aggregate, aggregate_read(modbus_function::read_input_registers, ModbusTable::input, 0, 3),
      WordOrder::big, SteadyClock::now() + 1h);
  REQUIRE_FALSE(reply.exception.has_value());
  CHECK(reply.registers.size() == 3);
}
