// Loading a Modbus RTU device profile (modbus_rtu/device_profile.h) from a TOML file, checked
// the way the configuration and its map files are checked (toml/): every problem in one pass, each reported as
// "FILE:LINE:COL: KEY: message" at the line it is about.
//
//   [[read]]                 # polled together, each block one FC 3/4 request
//   table = "input"          # "holding" or "input"
//   address = 0              # first register, 0-based (PDU addressing)
//   count = 8                # 1..125
//
//   [[value]]
//   name = "angle_x"         # angle_x and angle_y (degrees) feed the inclinometer pipeline
//   table = "input"
//   address = 0
//   type = "float32"         # int16, uint16, int32, uint32, float32, float64
//   word_order = "ABCD"      # ABCD (default), CDAB, BADC, DCBA
//   scale = 1.0              # value = raw * scale + offset
//   offset = 0.0
//   writable = false         # holding registers only; then optional min and max
//
//   [identity]               # optional: which values say who the device is
//   serial = "serial_number" # each the name of a [[value]]; numbers shown in decimal
//   firmware = "firmware_version"
//   model = "model_number"
#pragma once

#include <string>
#include <string_view>

#include "driver/file_error.h"
#include "driver/expected.h"
#include "modbus_rtu/device_profile.h"

namespace tiltgate::modbus_rtu {

// Profiles are small; a bigger file is a mistake (a log, a binary), not a profile.
inline constexpr std::uintmax_t kMaxProfileBytes = 1024 * 1024;

// Reads only a regular file of at most kMaxProfileBytes. A value may not take the name of a
// setting a map file writes by name: the common block's, and `setting_names` (every model's
// own, as the configuration's families give them).
Expected<DeviceProfile, FileErrors> load_device_profile(
    const std::string& path, std::span<const std::string_view> setting_names = {});
// The same from text in memory; `source_name` stands for the file name in errors.
Expected<DeviceProfile, FileErrors> parse_device_profile(
    std::string_view text, std::string_view source_name,
    std::span<const std::string_view> setting_names = {});

}  // namespace tiltgate::modbus_rtu
