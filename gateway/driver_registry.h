// The one place that knows which vendor driver serves which model: the rest of the core only
// sees SensorDriver.
#pragma once

#include <memory>

#include "config/config.h"
#include "driver/sensor_driver.h"

namespace tiltgate {

// Null for a model no driver serves (the config loader has rejected those already).
std::unique_ptr<SensorDriver> make_driver(const SensorConfig& sensor, const BusConfig& bus);

}  // namespace tiltgate
