// Answers checked Modbus requests: routes by unit id to a sensor, reads from its cache through
// its register map, turns register writes into queued sensor writes, and lists the sensor's
// identification objects for Read Device Identification (43 / 14).
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
  static ModbusResponse identify(const GatewaySensor& sensor);
  boost::asio::awaitable<ModbusResponse> write(GatewaySensor& sensor,
                                               const ModbusRequest& request);

  RouterOptions options_;
  std::array<GatewaySensor*, 256> units_{};
};

ModbusException exception_for(WriteErrorKind kind);
// The same, but a device's own Modbus exception is relayed with its code.
ModbusException exception_for(const WriteError& error);

// Every Read Device Identification object of a sensor (gateway/device_identification.h for
// the ids): vendor and product from its model, firmware and serial as the sensor reported
// them (empty until read), its name, bus and bus address, and the gateway's version.
std::vector<DeviceObject> device_objects(const GatewaySensor& sensor);

}  // namespace tiltgate
