#include "modbus_rtu/inclinometer_preset.h"

#include <span>

#include "mapping/value_codec.h"

namespace tiltgate::modbus_rtu {
namespace {

constexpr std::size_t kInputCount = 8;
constexpr std::size_t kHoldingCount = 3;

void put(std::vector<std::uint16_t>& bank, std::size_t address, std::size_t words, PointType type,
         double value, RegisterOrder order = RegisterOrder::abcd) {
  encode_number(std::span(bank).subspan(address, words), type, value, order, Rounding::nearest, 0.0);
}

}  // namespace

SimulatedDevice rtu_inclinometer(std::uint8_t slave, const InclinometerState& state) {
  SimulatedDevice device(slave, kHoldingCount, kInputCount);
  set_inclinometer_angles(device, state.angle_x, state.angle_y);
  put(device.input(), 6, 1, PointType::int16, state.temperature * 10.0);
  device.input()[7] = state.status;
  device.holding()[kInclinometerFilterRegister] = state.filter;
  put(device.holding(), 1, 2, PointType::uint32, state.serial_number, RegisterOrder::cdab);
  device.set_write_check([](std::uint16_t address, std::uint16_t value) {
    return address == kInclinometerFilterRegister && value >= kInclinometerMinFilter &&
           value <= kInclinometerMaxFilter;
  });
  return device;
}

void set_inclinometer_angles(SimulatedDevice& device, double angle_x, double angle_y) {
  put(device.input(), 0, 2, PointType::float32, angle_x);
  put(device.input(), 2, 2, PointType::float32, angle_y);
  put(device.input(), 4, 1, PointType::int16, angle_x * 100.0);
  put(device.input(), 5, 1, PointType::int16, angle_y * 100.0);
}

}  // namespace tiltgate::modbus_rtu
