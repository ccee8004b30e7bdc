// RequestRouter's pass-through: requests for unit ids a [[bus]] passes through are forwarded
// to the device with that address on the bus, under the same write rule as the cached sensors.
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

#include "gateway/bus_scheduler.h"
#include "modbus_tcp/modbus_request.h"
#include "gateway/request_router.h"

namespace tiltgate {

ModbusException exception_for(ForwardFailure failure) {
  switch (failure) {
    case ForwardFailure::busy: return ModbusException::busy;
    case ForwardFailure::expired:
    case ForwardFailure::no_response: return ModbusException::gateway_target_failed;
    case ForwardFailure::unframed: return ModbusException::device_failure;
  }
  return ModbusException::device_failure;
}

boost::asio::awaitable<ForwardedReply> RequestRouter::forward(std::uint8_t unit_id,
                                                              std::vector<std::uint8_t> pdu) {
  const std::shared_ptr<const Routes> routes = this->routes();
  BusScheduler* bus = routes->forwarded[unit_id];
  if (bus == nullptr) co_return Unexpected{ModbusException::gateway_path_unavailable};
  // As for the cached sensors: nobody on the plant network changes a device by default.
  if (!routes->options.writes && !reads_only(pdu)) {
    spdlog::debug("unit {}: function {:02X} not passed through: [server] writes is false",
                  unit_id, pdu.empty() ? 0 : pdu[0]);
    co_return Unexpected{ModbusException::illegal_function};
  }
  if (stopping_) co_return Unexpected{ModbusException::gateway_target_failed};
  // The server's write_timeout bounds the wait for the bus, as it does for writes.
  const auto deadline = SteadyClock::now() + routes->options.write_timeout;
  std::optional<ForwardedReply> reply = co_await boost::asio::co_spawn(
      bus_executor_, forward_on_bus(*bus, unit_id, std::move(pdu), deadline),
      boost::asio::use_awaitable);
  co_return std::move(*reply);
}

// On the buses' executor: the scheduler is theirs. In an optional only because co_spawn wants
// a result it can default-construct.
boost::asio::awaitable<std::optional<ForwardedReply>> RequestRouter::forward_on_bus(
    BusScheduler& bus, std::uint8_t unit_id, std::vector<std::uint8_t> pdu,
    SteadyClock::time_point deadline) {
  auto reply = co_await bus.forward(unit_id, std::move(pdu), deadline);
  if (!reply) co_return ForwardedReply{Unexpected{exception_for(reply.error())}};
  co_return ForwardedReply{std::move(*reply)};
}

}  // namespace tiltgate
