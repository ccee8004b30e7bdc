// After `tiltgate set` moved a sensor that came from a configuration file to another address or
// baud rate: the file follows it (config/config_edit.h), so the next `tiltgate run` finds it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "config/config.h"
#include "driver/expected.h"
#include "commission/commission_options.h"
#include "commission/set_plan.h"

namespace tiltgate {

// "updated FILE: sensor NAME address 223 -> 7" for each change written; none when the sensor
// was not taken from a file or the plan moved nothing; the reason when the file could not be
// changed.
Expected<std::optional<std::string>, std::string> update_config_file(const BusOptions& options,
                                                                      const SensorConfig& sensor,
                                                                      std::uint32_t old_address,
                                                                      const SetPlan& plan);

}  // namespace tiltgate
