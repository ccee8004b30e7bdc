// A scan as the engine runs it, for every front end (the command line, the web console): each
// address of a range is probed with the protocol's own probe (driver/scan.h) and a short
// time-out, and each address that answered is identified through the family's driver, as
// `info` does. With auto_baud, every rate the protocol allows is tried in turn. It reports
// events (commission/commission_events.h) and prints nothing.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <optional>
#include <vector>

#include "commission/commission_bus.h"
#include "commission/commission_events.h"
#include "commission/commission_options.h"
#include "commission/scan_plan.h"

namespace tiltgate {

// A scan, checked and ready to run: the bus to open, what to probe and how.
struct PreparedScan {
  CommissionTarget bus;
  // A sensor standing for those to be found (its model and the family's keys, such as a
  // device profile), when the options gave one; none when the family's sensors need a key
  // the options do not give (they are then found, but not identified).
  std::optional<SensorConfig> model_sensor;
  ProtocolEntry protocol;
  std::vector<std::uint32_t> addresses;
  bool auto_baud = false;
  bool broadcast = false;
  std::optional<std::int64_t> probe_timeout_ms;
  // The family's keys every sensor gives, with the values the scan was given, for the
  // configuration of what it found (a front end may write a path relative to its file).
  std::vector<SensorKeyValue> sensor_keys;
};

// Checks the bus and scan options together; every error names its option. `options.config_out`
// and `force` are the front end's to check: the engine writes no file.
Expected<PreparedScan, UsageErrors> prepare_scan(BusOptions bus_options,
                                                 const ScanOptions& options, FamilyList families);

// Runs the scan on `bus` (opened from `scan.bus`, or a command's line on a served bus) and
// returns the exit code: 0 when a sensor answered (or `stopping` turned true), 1 when none did
// or the bus failed. Every outcome is an event on `report`, the end a ScanFinishedEvent or a
// FailedEvent.
boost::asio::awaitable<int> scan_bus(CommissionBus& bus, const PreparedScan& scan,
                                     const EventSink& report, const bool& stopping);

}  // namespace tiltgate
