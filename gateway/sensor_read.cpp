#include "gateway/sensor_read.h"

namespace tiltgate {

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

void read_sensor(const GatewaySensor& sensor, const SensorSnapshot& snapshot,
                 const ModbusRequest& request, WordOrder order, SteadyClock::time_point now,
                 ModbusResponse& response, RegisterImage* image) {
  response.exception.reset();
  response.registers.clear();
  response.bits.clear();
  response.device_objects.clear();
  const auto view = sensor.view(snapshot, now, order);
  const auto table = table_of(request.table);
  if (table == RegisterTable::coil || table == RegisterTable::discrete) {
    auto read = read_bits(sensor.map, view, table, request.address, request.count, response.bits);
    if (!read) {
      response.bits.clear();
      response.exception = exception_for(read.error());
    }
    return;
  }
  response.registers.resize(request.count);  // within its capacity after the first reads
  auto read = image != nullptr
                  ? image->read(sensor.map, view, table, request.address, response.registers)
                  : read_registers(sensor.map, view, table, request.address, response.registers);
  if (!read) {
    response.registers.clear();
    response.exception = exception_for(read.error());
  }
}

}  // namespace tiltgate
