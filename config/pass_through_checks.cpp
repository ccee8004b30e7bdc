#include "config/pass_through_checks.h"

#include <fmt/format.h>

#include <algorithm>

#include "config/listeners.h"

namespace tiltgate::config {

using toml_input::ErrorList;
using toml_input::Located;

namespace {

std::string bus_name(const ParsedBus& bus) {
  return fmt::format("bus \"{}\" (line {})", bus.config.name, bus.where.header().line);
}

std::string sensor_name(const ParsedSensor& sensor) {
  return fmt::format("sensor \"{}\" (line {})", sensor.config.name, sensor.where.header().line);
}

bool passes(const ParsedBus& bus, std::int64_t id) {
  return std::find(bus.config.pass_through.begin(), bus.config.pass_through.end(), id) !=
         bus.config.pass_through.end();
}

// The line a key was written on, to report a clash at whichever of the two comes later.
int line_of(const Located& where, std::string_view key) { return where.at(key).line; }

void reject_across_buses(const std::vector<ParsedBus>& buses, ErrorList& errors) {
  for (std::size_t i = 0; i < buses.size(); ++i) {
    for (std::uint8_t id : buses[i].config.pass_through) {
      for (std::size_t j = 0; j < i; ++j) {
        // Unit ids are per listener ([[bus]] tcp_port).
        if (!passes(buses[j], id) || listener_of(buses[j].config) != listener_of(buses[i].config))
          continue;
        buses[i].where.report(errors, "pass_through",
                              fmt::format("unit id {} is already passed through on {}", id,
                                          bus_name(buses[j])));
        break;
      }
    }
  }
}

// A unit id answers either from a sensor's cache or from the device passed through, not both.
// On one listener, that is ([[bus]] tcp_port).
void reject_sensor_unit_id(const ParsedBus& bus, const ParsedSensor& sensor,
                           const std::vector<ParsedBus>& buses, ErrorList& errors) {
  if (!sensor.where.valid("unit_id") || !passes(bus, sensor.config.unit_id)) return;
  if (listener_of_bus(buses, sensor.config.bus) != listener_of(bus.config)) return;
  const int id = sensor.config.unit_id;
  if (line_of(sensor.where, "unit_id") > line_of(bus.where, "pass_through")) {
    sensor.where.report(errors, "unit_id",
                        fmt::format("unit_id {} is passed through on {}; a unit id is either a "
                                    "sensor or passed through",
                                    id, bus_name(bus)));
  } else {
    bus.where.report(errors, "pass_through",
                     fmt::format("unit id {} is the unit_id of {}; a unit id is either a sensor "
                                 "or passed through",
                                 id, sensor_name(sensor)));
  }
}

// A device passed through at a sensor's address: both would answer the same frames.
void reject_sensor_address(const ParsedBus& bus, const ParsedSensor& sensor, ErrorList& errors) {
  if (!sensor.where.valid("bus") || sensor.config.bus != bus.config.name) return;
  if (!sensor.where.valid("address") || !passes(bus, sensor.address)) return;
  if (line_of(sensor.where, "address") > line_of(bus.where, "pass_through")) {
    sensor.where.report(errors, "address",
                        fmt::format("{} is passed through on {}: the sensor and the device "
                                    "passed through would both answer it",
                                    sensor.address, bus_name(bus)));
  } else {
    bus.where.report(errors, "pass_through",
                     fmt::format("{} is the address of {} on this bus: the sensor and the "
                                 "device passed through would both answer it",
                                 sensor.address, sensor_name(sensor)));
  }
}

}  // namespace

void check_pass_through(const std::vector<ParsedBus>& buses,
                        const std::vector<ParsedSensor>& sensors, ErrorList& errors) {
  reject_across_buses(buses, errors);
  for (const ParsedBus& bus : buses) {
    if (bus.config.pass_through.empty() || !bus.where.valid("name")) continue;
    for (const ParsedSensor& sensor : sensors) {
      reject_sensor_unit_id(bus, sensor, buses, errors);
      reject_sensor_address(bus, sensor, errors);
    }
  }
}

}  // namespace tiltgate::config
