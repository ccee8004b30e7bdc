// Every key the configuration loader accepts, table by table, taken from the readers
// themselves (the keys each one asks for), so docs/configuration.md can be checked
// against the loader by a test and never fall behind it.
#pragma once

#include "toml/error_list.h"
#include "driver/family.h"

namespace tiltgate::config {

using toml_input::AcceptedKeys;

// Kinds of table: "server", "bus", "sensor", "sensor.mounting", "sensor.alarms", "sensor.map"
// (also a map file's top level) and "sensor.map.point" (also a map file's [[point]]).
AcceptedKeys accepted_keys(FamilyList families);

}  // namespace tiltgate::config
