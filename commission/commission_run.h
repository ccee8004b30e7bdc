// What the commissioning commands do alike around their own work: resolve the options, open
// the bus, run a coroutine on it until it ends or SIGINT/SIGTERM arrives.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <functional>
#include <string_view>

#include "commission/commission_bus.h"
#include "commission/commission_options.h"

namespace tiltgate {

// The command's work on the open bus; returns the exit code. `stopping` turns true on a
// signal, after which the line is stopped and every poll returns at once.
using CommissionWork =
    std::function<boost::asio::awaitable<int>(CommissionBus& bus, const bool& stopping)>;

// Prints usage errors ("tiltgate COMMAND: --baud: ...") and returns 2, or a bus that cannot be
// opened and returns 1; else the work's exit code (0 when stopped by a signal).
int run_commissioning(std::string_view command, const BusOptions& options, FamilyList families,
                      CommissionWork work);

// The same on a target the command resolved (and adjusted) itself: opens the bus and runs.
int run_commissioning_on(std::string_view command, const CommissionTarget& target,
                         CommissionWork work);

// Prints the usage errors as run_commissioning does; returns 2.
int report_usage_errors(std::string_view command, const UsageErrors& errors);

}  // namespace tiltgate
