// A command line's request run in the gateway (the control socket's `run`, control/
// command_runner.h): the engine's scan, info, watch, set or raw on a command's line of the bus
// the gateway serves (control/served_bus_line.h), its changes recorded under the command's Unix
// user, its events as JSON for the command to render. The request's options are read as the
// command line reads them (the command made their files' paths absolute); the configuration
// file `set` follows is the command's to update, not the gateway's.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <string>

#include "commission/commission_events.h"
#include "control/command_runner.h"
#include "driver/family.h"
#include "driver/family_commands.h"

namespace tiltgate {

// The runner the control socket is given (app/served_gateway.cpp).
CommandRunner requested_command_runner(FamilyList families, FamilyCommandsList commands);

// The same with its events as they are (exposed for tests).
boost::asio::awaitable<int> run_requested_command(FamilyList families, FamilyCommandsList commands,
                                                  std::string request, ServedBus bus,
                                                  WriteOrigin by, EventSink report,
                                                  CommandStop& stop);

}  // namespace tiltgate
