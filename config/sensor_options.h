// The [[sensor]] keys beyond bus and address: mounting, alarms and what a read of an offline
// sensor returns. Each checked on its own and against the sensor's model (its axes).
#pragma once

#include "config/config.h"
#include "toml/error_list.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::TableReader;

// mounting = { swap_axes, invert_x, invert_y, rotate_deg }
void read_mounting(TableReader& in, SensorConfig& sensor, ErrorList& errors,
                   FamilyList families);
// alarms = { x_high, x_low, y_high, y_low, tilt_high, hysteresis_deg, rate_limit_deg_s }
void read_alarms(TableReader& in, SensorConfig& sensor, ErrorList& errors,
                 FamilyList families);
// offline = "exception" | "last" | "substitute", substitute = <number>
void read_offline(TableReader& in, SensorConfig& sensor);

}  // namespace tiltgate::config
