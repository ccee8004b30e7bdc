// [[sensor]] alarms = {...}: the warning level's thresholds at the table's top, the danger
// level's in `danger = {...}`, the hysteresis and for_ms (docs/configuration.md, "alarms").
// Each threshold is checked on its own, against the sensor's model (its axes) and lever_m,
// and the two levels against each other.
#pragma once

#include "config/config.h"
#include "toml/error_list.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

// alarms = { x_high, x_low, y_high, y_low, tilt_high, rate_limit_deg_s, displacement_high_mm,
//            hysteresis_deg, hysteresis_mm, for_ms, danger = { the thresholds again } }
// Read after lever_m (a displacement alarm needs it).
void read_alarms(toml_input::TableReader& in, SensorConfig& sensor,
                 toml_input::ErrorList& errors, FamilyList families);

}  // namespace tiltgate::config
