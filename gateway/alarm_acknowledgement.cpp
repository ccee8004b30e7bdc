#include "gateway/alarm_acknowledgement.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "audit/audit_trail.h"
#include "line_scheduling/bus_scheduler.h"

namespace tiltgate {

namespace {

ModbusResponse refused(ModbusException code) {
  ModbusResponse response;
  response.exception = code;
  return response;
}

// Every coil from `address` for `count` is an acknowledge_alarms point.
bool only_acknowledge_coils(const RegisterMap& map, std::uint16_t address, std::size_t count) {
  for (std::size_t i = 0; i < count; ++i) {
    const auto points = map.overlapping(RegisterTable::coil, address + i, 1);
    if (points.empty() || points.front().source != ValueSource::acknowledge_alarms) return false;
  }
  return true;
}

}  // namespace

ModbusResponse acknowledge_alarms(GatewaySensor& sensor, const ModbusRequest& request) {
  if (!sensor.map.has_table(RegisterTable::coil)) return refused(ModbusException::illegal_function);
  if (!only_acknowledge_coils(sensor.map, request.address, request.bits.size()))
    return refused(ModbusException::illegal_address);
  if (std::none_of(request.bits.begin(), request.bits.end(), [](bool bit) { return bit; }))
    return ModbusResponse{};
  AuditTrail* trail = sensor.bus ? sensor.bus->audit() : nullptr;
  const std::string name = sensor.config.bus + "/" + sensor.config.name;
  const std::uint16_t before = sensor.processing.derived().alarms_latched;
  const auto record = [&](std::string result) {
    if (trail)
      trail->record({0, request.origin, name, "acknowledge_alarms",
                     fmt::format("latched {:#06x}", before), "1", std::move(result)});
  };
  // [audit] when_full = "refuse": no change the trail cannot keep on disk.
  if (trail && !trail->accepts_changes()) {
    std::string why = "refused: ";
    why += kAuditRefusesChanges;
    record(std::move(why));
    return refused(ModbusException::device_failure);
  }
  sensor.processing.acknowledge_alarms();
  sensor.publish();
  spdlog::info("{}: alarms acknowledged (latched {:#06x}, now {:#06x})", name, before,
               sensor.processing.derived().alarms_latched);
  record("ok");
  return ModbusResponse{};
}

}  // namespace tiltgate
