// What the commissioning commands do alike around their own work: resolve the options, then
// either have a running gateway that serves the bus run the command (its control socket,
// control/gateway_command.h) or open the bus and run the work on it, until it ends or
// SIGINT/SIGTERM arrives. Either way the command's events reach the same renderer.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <functional>
#include <string_view>

#include "commission_wire/command_request.h"
#include "commission/commission_bus.h"
#include "commission/commission_events.h"
#include "commission/commission_options.h"

namespace tiltgate {

// The command's work on the open bus; returns the exit code. `stopping` turns true on a
// signal, after which the line is stopped and every poll returns at once.
using CommissionWork =
    std::function<boost::asio::awaitable<int>(CommissionBus& bus, const bool& stopping)>;

// The same command as a running gateway that serves the bus runs it: what to ask its engine,
// where the events it sends back go (the renderer `work` reports to), and what the command
// does after the gateway's run with its exit code (`set` updates the configuration file it
// came from); returns the command's exit code.
struct GatewayRequest {
  CommandRequest request;
  EventSink report;
  std::function<int(int exit_code)> after;  // none: the exit code as it is
};

// Prints usage errors ("tiltgate COMMAND: --baud: ...") and returns 2, or a bus that cannot be
// opened and returns 1; else the work's exit code (0 when stopped by a signal).
int run_commissioning(std::string_view command, const BusOptions& options, FamilyList families,
                      CommissionWork work, GatewayRequest through_gateway);

// The same on a target the command resolved (and adjusted) itself: opens the bus and runs.
int run_commissioning_on(std::string_view command, const CommissionTarget& target,
                         CommissionWork work, GatewayRequest through_gateway);

// Prints the usage errors as run_commissioning does; returns 2.
int report_usage_errors(std::string_view command, const UsageErrors& errors);

}  // namespace tiltgate
