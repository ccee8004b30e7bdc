// What the gateway does with a command's `run` (control/control_protocol.h): the commissioning
// engine's work on the served bus the command asked for. The composition root makes it from the
// engine (app/served_gateway.cpp, commission_wire/requested_command.h), so this room carries
// requests and events without knowing what a scan or a setting is.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <functional>
#include <string>

#include "audit/audit_record.h"
#include "control/served_bus_line.h"

namespace tiltgate {

// How a running command learns that it is to stop: the engineer pressed Ctrl-C, or the command
// went away. `requested` is what the engine's loops look at; `on_request`, set by the runner
// while it runs, cancels what is on its line so that a suspended poll returns at once.
struct CommandStop {
  bool requested = false;
  std::function<void()> on_request;
  void request() {
    requested = true;
    if (on_request) on_request();
  }
};

// Runs `request` (one JSON object, commission_wire/command_request.h) on `bus`, its changes recorded
// under `by`; each event goes to `emit` as one JSON object (commission_wire/event_json.h), in the
// order they happen. Returns the command's exit code; never throws (a failure is an event).
using CommandRunner = std::function<boost::asio::awaitable<int>(
    std::string request, ServedBus bus, WriteOrigin by,
    std::function<void(std::string)> emit, CommandStop& stop)>;

}  // namespace tiltgate
