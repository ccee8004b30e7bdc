// Answers checked Modbus requests: routes by unit id to a sensor, reads from its cache through
// its register map, turns register writes into queued sensor writes, and lists the sensor's
// identification objects for Read Device Identification (43 / 14).
#pragma once

#include <array>
#include <chrono>
#include <memory>
#include <span>

#include "config/config.h"
#include "gateway/gateway_aggregate.h"
#include "gateway/gateway_sensor.h"
#include "gateway/modbus_types.h"

namespace tiltgate {

class BusScheduler;
enum class ForwardFailure;

struct RouterOptions {
  bool writes = false;
  WordOrder word_order = WordOrder::big;
  std::chrono::milliseconds write_timeout{3000};
};

class RequestRouter : public ModbusRequestHandler {
 public:
  explicit RequestRouter(RouterOptions options) : options_(options) {}

  // Answers `sensor`'s unit id (which must be free). This overload does not own the sensor:
  // the caller keeps it alive.
  void add(GatewaySensor& sensor);
  // The same, and a request being answered keeps its sensor alive to the end, even when a
  // reload drops the sensor meanwhile.
  void add(std::shared_ptr<GatewaySensor> sensor);
  GatewaySensor* find(std::uint8_t unit_id) const { return units_[unit_id].get(); }
  // Answers the aggregate's unit id (which must be free) from its sensors' caches.
  void add(std::shared_ptr<GatewayAggregate> aggregate);
  // Forgets every sensor, aggregate and pass-through unit id (a reload adds the new set at once).
  // Requests already being answered finish with the sensor or bus they started with.
  void clear();
  // Applies to the next request.
  void set_options(RouterOptions options) { options_ = options; }

  boost::asio::awaitable<ModbusResponse> handle(const ModbusRequest& request) override;

  // Pass-through (gateway/request_forwarding.cpp): requests for `unit_id` go to the device
  // with that address on `bus`. The unit id must be no sensor's.
  void pass_through(std::uint8_t unit_id, BusScheduler& bus) { forwarded_[unit_id] = &bus; }
  bool passes_through(std::uint8_t unit_id) const override {
    return forwarded_[unit_id] != nullptr;
  }
  boost::asio::awaitable<ForwardedReply> forward(std::uint8_t unit_id,
                                                 std::vector<std::uint8_t> pdu) override;

 private:
  ModbusResponse read(const GatewaySensor& sensor, const ModbusRequest& request) const;
  static ModbusResponse identify(const GatewaySensor& sensor);
  boost::asio::awaitable<ModbusResponse> write(GatewaySensor& sensor,
                                               const ModbusRequest& request);

  RouterOptions options_;
  std::array<std::shared_ptr<GatewaySensor>, 256> units_{};
  std::array<std::shared_ptr<GatewayAggregate>, 256> aggregates_{};
  std::array<BusScheduler*, 256> forwarded_{};
};

ModbusException exception_for(ForwardFailure failure);

ModbusException exception_for(WriteErrorKind kind);
// The same, but a device's own Modbus exception is relayed with its code.
ModbusException exception_for(const WriteError& error);

// Every Read Device Identification object of a sensor (gateway/device_identification.h for
// the ids): vendor and product from its model, firmware and serial as the sensor reported
// them (empty until read), its name, bus and bus address, and the gateway's version.
std::vector<DeviceObject> device_objects(const GatewaySensor& sensor);

}  // namespace tiltgate
