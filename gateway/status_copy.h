// The copy of the running core's state that the services show (gateway/gateway_status.h),
// taken from a sensor, a bus and a Modbus listener one at a time: plain values, so the text
// built from it is pure and testable without a bus.
#pragma once

#include <optional>

#include "driver/line.h"
#include "line_scheduling/bus_scheduler.h"
#include "line_scheduling/gateway_sensor.h"
#include "gateway/gateway_status.h"
#include "modbus_tcp/modbus_tcp_server.h"

namespace tiltgate {

// The sensor as it is now: identity, reading after mounting, its staleness and counters.
SensorStatus sensor_status(const GatewaySensor& sensor, SteadyClock::time_point now);

// Its failed polls and failed exchanges by cause.
FailureCounts failure_counts(const SensorCounters& counters);
ExchangeCounts exchange_counts(const SensorCounters& counters);

// The bus's configuration and counters, its scheduler's and its line's; `polls_per_s` and
// `busy_share` are the rates measured over the last seconds (none until counted).
BusStatus bus_status(const BusConfig& config, const BusSchedulerStats& stats, const LineStats& line,
                     std::optional<double> polls_per_s, std::optional<double> busy_share);

// The failures of the sensors on `bus`, since start and recent (none when one of them has none
// yet), into its status.
void add_sensor_failures(BusStatus& bus, const std::vector<SensorStatus>& sensors);

// Adds one Modbus listener's connections and request counts to `status`' totals.
void add_listener_counts(GatewayStatus& status, const ModbusTcpServer& listener);

// A rate as the status shows it: an estimate over a few seconds, to `scale` (100: 0.01).
std::optional<double> rounded(std::optional<double> value, double scale);

}  // namespace tiltgate
