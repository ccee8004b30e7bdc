#include "gateway/request_router.h"

#include <spdlog/spdlog.h>

#include "gateway/bus_scheduler.h"

namespace tiltgate {

namespace {

ModbusResponse failure(ModbusException code) {
  ModbusResponse response;
  response.exception = code;
  return response;
}

RegisterTable table_of(ModbusTable table) {
  switch (table) {
    case ModbusTable::coil: return RegisterTable::coil;
    case ModbusTable::discrete: return RegisterTable::discrete;
    case ModbusTable::input: return RegisterTable::input;
    case ModbusTable::holding: return RegisterTable::holding;
  }
  return RegisterTable::holding;
}

ModbusException exception_for(MapFault fault) { return ModbusException(std::uint8_t(fault)); }

}  // namespace

ModbusException exception_for(WriteErrorKind kind) {
  switch (kind) {
    case WriteErrorKind::not_supported: return ModbusException::illegal_address;
    case WriteErrorKind::bad_value:
    case WriteErrorKind::rejected: return ModbusException::illegal_value;
    case WriteErrorKind::refused: return ModbusException::device_failure;
    case WriteErrorKind::busy: return ModbusException::busy;
    case WriteErrorKind::no_response: return ModbusException::gateway_target_failed;
  }
  return ModbusException::device_failure;
}

void RequestRouter::add(GatewaySensor& sensor) { units_[sensor.config.unit_id] = &sensor; }

boost::asio::awaitable<ModbusResponse> RequestRouter::handle(const ModbusRequest& request) {
  GatewaySensor* sensor = units_[request.unit_id];
  if (sensor == nullptr) co_return failure(ModbusException::gateway_path_unavailable);
  if (!request.is_write) co_return read(*sensor, request);
  co_return co_await write(*sensor, request);
}

ModbusResponse RequestRouter::read(const GatewaySensor& sensor,
                                   const ModbusRequest& request) const {
  const auto view = sensor.view(SteadyClock::now(), options_.word_order);
  const auto table = table_of(request.table);
  ModbusResponse response;
  if (table == RegisterTable::coil || table == RegisterTable::discrete) {
    auto bits = read_bits(sensor.map, view, table, request.address, request.count);
    if (!bits) return failure(exception_for(bits.error()));
    response.bits = std::move(*bits);
  } else {
    auto words = read_registers(sensor.map, view, table, request.address, request.count);
    if (!words) return failure(exception_for(words.error()));
    response.registers = std::move(*words);
  }
  return response;
}

boost::asio::awaitable<ModbusResponse> RequestRouter::write(GatewaySensor& sensor,
                                                            const ModbusRequest& request) {
  // A gateway must not let anyone on the plant network re-address a sensor by default.
  if (!options_.writes) co_return failure(ModbusException::illegal_function);
  if (request.table != ModbusTable::holding) {
    const auto table = table_of(request.table);
    co_return failure(sensor.map.has_table(table) ? ModbusException::illegal_address
                                                  : ModbusException::illegal_function);
  }
  auto plan = plan_register_write(sensor.map, options_.word_order, request.address,
                                  request.registers);
  if (!plan) co_return failure(exception_for(plan.error()));
  for (const PlannedWrite& step : *plan) {
    auto checked = sensor.driver->check_write(*step.point->write, step.value);
    if (!checked) co_return failure(exception_for(checked.error().kind));
  }
  const auto deadline = SteadyClock::now() + options_.write_timeout;
  for (const PlannedWrite& step : *plan) {
    auto done = co_await sensor.bus->write(sensor, *step.point->write, step.value, deadline);
    if (!done) {
      spdlog::warn("{}: write {} = {} failed: {}", sensor.config.name, step.point->name,
                   step.value, done.error().detail);
      co_return failure(exception_for(done.error().kind));
    }
    spdlog::info("{}: wrote {} = {}", sensor.config.name, step.point->name, step.value);
    std::copy(step.words.begin(), step.words.end(),
              sensor.written.begin() + step.point->address);
  }
  co_return ModbusResponse{};
}

}  // namespace tiltgate
