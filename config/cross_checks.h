// Checks across tables: names and unit ids that must be unique, two buses on one tty or on one
// device server's port, each sensor against its bus (protocol, address range, address
// clashes), and the two MQTT clients against each other.
#pragma once

#include <vector>

#include "toml/error_list.h"
#include "config/sections.h"

namespace tiltgate::config {

using toml_input::ErrorList;

void check_buses(const std::vector<ParsedBus>& buses, ErrorList& errors);
void check_sensors(const std::vector<ParsedSensor>& sensors, const std::vector<ParsedBus>& buses,
                   ErrorList& errors, FamilyList families);
// [mqtt] and [sparkplug] together: not one client id on one broker (the broker would keep
// disconnecting one for the other). `sparkplug_at`: where the [sparkplug] table starts.
void check_feeds(const MqttConfig& mqtt, const SparkplugConfig& sparkplug,
                 toml_input::Place sparkplug_at, ErrorList& errors);

}  // namespace tiltgate::config
