// `set` as the engine runs it, for every front end: the Configurator's settings for one sensor,
// through its driver (which unlocks and locks again as the protocol needs), then the sensor's
// state read back as `info` shows it. The writes are planned first (commission/set_plan.h) and
// every value checked before anything is sent. What happens is reported as events
// (commission/commission_events.h): each write's answer, the move, the restart, the
// configuration file that follows it, the sensor read back. Nothing is printed.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <string>

#include "commission/commission_bus.h"
#include "commission/commission_events.h"
#include "commission/set_plan.h"
#include "driver/family_commands.h"

namespace tiltgate {

struct SetRequest {
  SetArguments arguments;
  // The configuration file the sensor was taken from, which follows a move to another address
  // or baud rate (commission/set_config_update.h); empty: none.
  std::string config_file;
};

// Sets the bus's one sensor and returns the exit code: 0 acknowledged and read back (or
// `stopping` turned true), 1 when the sensor did not answer, refused, or could not be read back
// (or the configuration file could not follow it), 2 when the request cannot be made of it (a
// FailedEvent says why; nothing was sent).
boost::asio::awaitable<int> set_sensor(CommissionBus& bus, const SetRequest& request,
                                       FamilyCommandsList commands, const EventSink& report,
                                       const bool& stopping);

}  // namespace tiltgate
