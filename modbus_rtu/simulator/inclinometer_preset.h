// A simulated dual-axis Modbus RTU inclinometer whose registers match the example device
// profile examples/devices/rtu-inclinometer.toml (a test loads the profile and decodes the
// preset's registers with it, so the two cannot drift apart).
//
// Input registers (FC 4):   0-1 angle X, float32 ABCD, degrees
//                           2-3 angle Y, float32 ABCD, degrees
//                           4   angle X, int16, 0.01 degree
//                           5   angle Y, int16, 0.01 degree
//                           6   temperature, int16, 0.1 degC
//                           7   status, uint16 (0: ok)
// Holding registers (FC 3): 0   filter, uint16, 1..8 (writable; other values: exception 03)
//                           1-2 serial number, uint32 CDAB (read-only: exception 03)
//                           3   firmware version, uint16, x 0.01 (102: 1.02; read-only)
//                           4   model number, uint16 (read-only)
// It also tells who it is without a profile: FC 17 (server id 0x2A, run indicator ON, then
// "tiltgate RTU inclinometer") and FC 43 / 14 (vendor, product code, revision, product name,
// model name).
#pragma once

#include <cstdint>

#include "modbus_rtu/simulator/simulated_device.h"

namespace tiltgate::modbus_rtu {

struct InclinometerState {
  double angle_x = 0.0;  // degrees
  double angle_y = 0.0;
  double temperature = 21.5;  // degC
  std::uint16_t status = 0;
  std::uint16_t filter = 4;
  std::uint32_t serial_number = 20240917;
  std::uint16_t firmware_version = 102;  // 1.02
  std::uint16_t model_number = 360;
};

inline constexpr std::uint16_t kInclinometerFilterRegister = 0;
inline constexpr std::uint16_t kInclinometerMinFilter = 1;
inline constexpr std::uint16_t kInclinometerMaxFilter = 8;

SimulatedDevice rtu_inclinometer(std::uint8_t slave, const InclinometerState& state = {});
// Sets both angle encodings (float32 and 0.01-degree int16).
void set_inclinometer_angles(SimulatedDevice& device, double angle_x, double angle_y);

}  // namespace tiltgate::modbus_rtu
