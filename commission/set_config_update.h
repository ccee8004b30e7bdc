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

// The configuration file a sensor was taken from, which follows what `set` moves: the options'
// --config, unless --port gave the bus; empty: none.
std::string followed_config_file(const BusOptions& options);

// "updated FILE: sensor NAME address 223 -> 7" for each change written; none when there is no
// file (`config_file` empty) or the plan moved nothing; the reason when the file could not be
// changed.
Expected<std::vector<std::string>, std::string> update_config_file(const std::string& config_file,
                                                                   const SensorConfig& sensor,
                                                                   std::uint32_t old_address,
                                                                   const SetPlan& plan);

}  // namespace tiltgate
