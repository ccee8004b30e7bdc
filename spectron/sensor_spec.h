// The module list of `tiltgate sim spectron --sensors dyna:1,dyna:2`, as simulator options.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"
#include "spectron/protocol.h"
#include "spectron/simulated_dyna.h"

namespace tiltgate::spectron {

// Comma-separated `dyna[:address]` items (model in any case). The address range and default
// follow the bus protocol: 0..255, default 0 (the factory address) on a 9-bit bus; 1..250,
// default 1 on a Modbus-ASCII bus (0 is not a Modbus-ASCII address). Addresses are unique.
// So that a demo shows distinct, living modules, each gets serial 10000 + address, counts
// swaying around 1000 * (i + 1) (amplitude 50, period 30 s; i capped at 29) and a raw
// temperature of 250 + 10 * i (i = position in the list).
// `shared_addresses`: two modules may have one address (their replies collide).
Expected<std::vector<SimulatedDynaOptions>, std::string> parse_sensor_spec(
    std::string_view spec, Protocol protocol, bool shared_addresses = false);

}  // namespace tiltgate::spectron
