// Answers checked Modbus requests: routes by unit id to a sensor, reads from its cache through
// its register map, and turns register writes into queued sensor writes.
#pragma once

#include <array>
#include <chrono>

#include "config/config.h"
#include "gateway/gateway_sensor.h"
#include "gateway/modbus_types.h"

namespace tiltgate {

struct RouterOptions {
  bool writes = false;
  WordOrder word_order = WordOrder::big;
  std::chrono::milliseconds write_timeout{3000};
};

class RequestRouter : public ModbusRequestHandler {
 public:
  explicit RequestRouter(RouterOptions options) : options_(options) {}

  void add(GatewaySensor& sensor);  // its unit id must be free
  GatewaySensor* find(std::uint8_t unit_id) const { return units_[unit_id]; }

  boost::asio::awaitable<ModbusResponse> handle(const ModbusRequest& request) override;

 private:
  ModbusResponse read(const GatewaySensor& sensor, const ModbusRequest& request) const;
  boost::asio::awaitable<ModbusResponse> write(GatewaySensor& sensor,
                                               const ModbusRequest& request);

  RouterOptions options_;
  std::array<GatewaySensor*, 256> units_{};
};

ModbusException exception_for(WriteErrorKind kind);

}  // namespace tiltgate
