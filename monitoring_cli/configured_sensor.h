// What `tiltgate baseline` and `tiltgate history` both start from: the gateway's configuration
// file and one sensor of it, or, when the file is not one the gateway would run or has no such
// sensor, the reason said on standard error as the command's own line.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "config/config.h"
#include "driver/family.h"

namespace tiltgate {

struct ConfiguredSensor {
  Config config;
  SensorConfig sensor;
};

std::optional<ConfiguredSensor> load_configured_sensor(std::string_view command,
                                                       const std::string& config_path,
                                                       const std::string& sensor,
                                                       FamilyList families);

}  // namespace tiltgate
