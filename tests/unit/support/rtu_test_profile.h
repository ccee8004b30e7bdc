// A device profile for the Modbus RTU simulator's inclinometer preset
// (modbus_rtu/simulator/inclinometer_preset.h) with writable values, shared by the unit, sim and e2e tests
// of profile values in maps and writes. filter_level accepts up to 20 here while the device
// refuses anything above 8 (exception 03), so a test can reach the device's own refusal; the
// serial number is writable here but read-only on the device.
#pragma once

#include <cstddef>

namespace tiltgate::test {

inline constexpr const char* kRtuTestProfile = R"([[read]]
table = "input"
address = 0
count = 8

[[read]]
table = "holding"
address = 0
count = 3

[[value]]
name = "angle_x"
table = "input"
address = 0
type = "float32"

[[value]]
name = "angle_y"
table = "input"
address = 2
type = "float32"

[[value]]
name = "temperature"
table = "input"
address = 6
type = "int16"
scale = 0.1

[[value]]
name = "filter_level"
table = "holding"
address = 0
type = "uint16"
writable = true
max = 20

[[value]]
name = "serial_number"
table = "holding"
address = 1
type = "uint32"
word_order = "CDAB"
writable = true
)";

// The values' indices in profile order (Reading::device_values, WriteTarget::device_value).
namespace rtu_test_value {
inline constexpr std::size_t angle_x = 0;
inline constexpr std::size_t angle_y = 1;
inline constexpr std::size_t temperature = 2;
inline constexpr std::size_t filter_level = 3;
inline constexpr std::size_t serial_number = 4;
}  // namespace rtu_test_value

}  // namespace tiltgate::test
