// The [[sensor]] keys beyond bus and address: mounting, the baseline and lever, and what a read
// of an offline sensor returns (the alarms: config/alarm_options.h). Each checked on its own
// and against the sensor's model (its axes).
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
// lever_m = <metres>, baseline = { x, y } (degrees after mounting)
void read_baseline(TableReader& in, SensorConfig& sensor, ErrorList& errors,
                   FamilyList families);
// burst_s, pre_trigger_s, burst_rate_deg_s: triggered bursts (docs/monitoring.md, "Bursts")
void read_burst(TableReader& in, SensorConfig& sensor);
// offline = "exception" | "last" | "substitute", substitute = <number>
void read_offline(TableReader& in, SensorConfig& sensor);

}  // namespace tiltgate::config
