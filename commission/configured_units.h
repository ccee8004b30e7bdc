// What a configuration file already holds, for what a scan proposes to add to it
// (docs/commissioning.md, "`tiltgate scan`: finding the sensors on a bus"): which addresses of
// the scanned bus are configured sensors, and which Modbus unit ids are taken on any bus. The
// command line's `scan --config-out`, a scan through the control socket and the web console's
// scan all propose from it, so they agree. Pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "config/config.h"

namespace tiltgate {

struct ConfiguredUnits {
  // The scanned bus's sensors: address -> name. A bus speaks one protocol, so one family: its
  // bus and address name a configured sensor.
  std::map<std::uint32_t, std::string> on_bus;
  // Every unit id the configuration serves, on every bus: its sensors', its aggregates', its
  // pass-through ids (`tiltgate check` refuses a unit id given twice among them).
  std::set<std::uint8_t> unit_ids;
};

// What `config` holds, seen from its bus `bus`.
ConfiguredUnits configured_units(const Config& config, std::string_view bus);

// The lowest `count` unit ids of 1..247 that are not in `taken`, ascending; fewer when fewer
// are free.
std::vector<std::uint8_t> free_unit_ids(const std::set<std::uint8_t>& taken, std::size_t count);

}  // namespace tiltgate
