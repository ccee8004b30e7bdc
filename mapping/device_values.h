// Matching a register map's points with one sensor's own values (driver/device_value.h). A map
// file names such a value as it names a built-in source or setting (`source = "temperature"`,
// `write = "setpoint"`); which values there are depends on the sensor (its device profile), so
// the names are kept on the point when the map is read and matched here for each sensor that
// uses the map. A name the sensor does not have stays unmatched, and the map's checks report it
// (mapping/map_validation.h).
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/device_value.h"
#include "mapping/point.h"

namespace tiltgate {

// Sets each point's device_index (source device_value) and device write target from `values`.
void resolve_device_values(std::span<Point> points, std::span<const DeviceValue> values);

// What is wrong with one resolved point's device-value names, at the map-file key it is about:
// a name that is neither built in (a source, or a setting of `families`) nor one of `values`,
// or a write of a value the device profile does not make writable.
struct DeviceNameProblem {
  std::string key;  // "source" or "write"
  std::string message;
};
std::vector<DeviceNameProblem> device_name_problems(FamilyList families, const Point& p,
                                                    std::span<const DeviceValue> values);

// The index of the value called `name`, or none.
std::optional<std::size_t> find_device_value(std::span<const DeviceValue> values,
                                             std::string_view name);

}  // namespace tiltgate
