// The sensor list of `tiltgate sim rieker --sensors h6:223,h4360:101`, as simulator options.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"
#include "rieker/simulated_sensor.h"

namespace tiltgate::rieker {

// Comma-separated `model[:address]` items; model is h6 or h4360 (any case), address 1..65000
// (default 223) and unique. So that a demo shows distinct, living sensors, each gets the
// serial "96" followed by its address (zero padded to 5 digits) and angles that sway slowly
// around a different base: X = 1 + i degrees, Y = -(1 + i) (i = position in the list),
// amplitude 0.25 degrees, period 30 s.
// `shared_addresses`: two sensors may have one address (their replies collide).
Expected<std::vector<SimulatedSensorOptions>, std::string> parse_sensor_spec(
    std::string_view spec, bool shared_addresses = false);

}  // namespace tiltgate::rieker
