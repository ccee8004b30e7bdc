// One Modbus TCP connection's reader of a RequestRouter (modbus_tcp/modbus_types.h,
// ModbusReader): answers reads at once, on the connection's thread, from a table and snapshots
// it keeps between requests. Each read compares two generation numbers (the router's table,
// the sensor's snapshot) with the ones it kept, and takes a new table or snapshot only when
// one moved: a read of a sensor that did not change since the last takes no lock and touches
// no reference count the bus thread or another connection touches too
// (docs/performance.md, "The Modbus read path").
//
// What it keeps lives on until its next read or its end: an idle connection may hold a
// sensor a reload dropped, which holds no I/O (line_scheduling/gateway_sensor.h).
#pragma once

#include <array>
#include <cstdint>
#include <memory>

#include "gateway/request_router.h"
#include "gateway/unit_routes.h"

namespace tiltgate {

class RouterReader : public ModbusReader {
 public:
  explicit RouterReader(const RequestRouter& router) : router_(router) {}

  // Everything answer_from_cache() answers (gateway/request_router.h): all but a write that
  // goes to its bus and a unit passed through, which RequestRouter::handle() and forward() take.
  bool read(const ModbusRequest& request, ModbusResponse& response,
            SteadyClock::time_point now) override;
  bool passes_through(std::uint8_t unit_id) override;

 private:
  // The snapshot of one sensor as last taken, the generation it was taken at, and its
  // registers as rendered for reads (kept across snapshots: it only grows once).
  struct KeptSnapshot {
    const GatewaySensor* sensor = nullptr;
    std::uint64_t generation = 0;
    std::shared_ptr<const SensorSnapshot> snapshot;
    RegisterImage image;
  };

  const UnitRoutes& routes();
  // The kept snapshot of `sensor` (its snapshot null: never polled).
  KeptSnapshot& snapshot_of(const GatewaySensor& sensor, std::uint8_t unit_id);

  const RequestRouter& router_;
  std::shared_ptr<const UnitRoutes> routes_;
  std::uint64_t routes_generation_ = 0;
  // By unit id modulo 16: a client that polls up to 16 consecutive units keeps all of them.
  std::array<KeptSnapshot, 16> kept_{};
  CachedReadScratch scratch_;
};

}  // namespace tiltgate
