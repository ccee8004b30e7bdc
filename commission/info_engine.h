// `info` as the engine runs it, for every front end: the vendor User App's Sensor Info, for each
// sensor of the bus. A sensor whose model the options do not name is polled as each model of its
// family until one measures (commission/model_detection.h). A sensor without its driver (a device
// whose family needs a --device profile, given none) is asked with its protocol's own requests
// what it says of itself (FamilyCommands::identify). Each sensor is one SensorReadingEvent
// (commission/commission_events.h), with a FailedEvent after it when it told too little; nothing
// is printed.
#pragma once

#include <boost/asio/awaitable.hpp>

#include "commission/commission_bus.h"
#include "commission/commission_events.h"
#include "driver/family_commands.h"

namespace tiltgate {

// Reads every sensor of `bus` in turn and returns the exit code: 0 when each told its identity
// and gave a reading (or `stopping` turned true), 1 when one did not, 2 when a sensor without
// its driver has a family that can be asked nothing without it.
boost::asio::awaitable<int> show_info(CommissionBus& bus, FamilyCommandsList commands,
                                      const EventSink& report, const bool& stopping);

}  // namespace tiltgate
