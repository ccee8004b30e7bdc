#include "modbus_rtu/simulator/inclinometer_preset.h"

#include <fmt/format.h>

#include <span>
#include <string>

#include "mapping/value_codec.h"

namespace tiltgate::modbus_rtu {
namespace {

constexpr std::size_t kInputCount = 8;
constexpr std::size_t kHoldingCount = 5;

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
  device.holding()[3] = state.firmware_version;
  device.holding()[4] = state.model_number;
  SimulatedIdentification identification;
  identification.server_id = 0x2A;
  identification.additional_data = "tiltgate RTU inclinometer";
  identification.objects = {{0x00, "tiltgate"},
                            {0x01, "TG-RTU-INC"},
                            {0x02, fmt::format("{}.{:02}", state.firmware_version / 100,
                                               state.firmware_version % 100)},
                            {0x04, "simulated RTU inclinometer"},
                            {0x05, std::to_string(state.model_number)}};
  device.set_identification(std::move(identification));
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
