// Makes the driver of a configured sensor through its family's descriptor: the rest of the
// core only sees SensorDriver.
#pragma once

#include <memory>

#include "config/config.h"
#include "driver/family.h"
#include "driver/sensor_driver.h"

namespace tiltgate {

// What the family's driver factory gets for this sensor on this bus.
DriverSetup driver_setup(const SensorConfig& sensor, const BusConfig& bus);

// Null for a model no family serves on the bus's protocol (the config loader has rejected
// those already).
std::unique_ptr<SensorDriver> make_driver(FamilyList families, const SensorConfig& sensor,
                                          const BusConfig& bus);

}  // namespace tiltgate
