#include "spectron/default_map.h"

#include <vector>

#include "mapping/common_block.h"
#include "spectron/settings.h"

namespace tiltgate::spectron {
namespace {

using T = PointType;
using S = ValueSource;
using W = WriteTarget;

constexpr std::uint16_t kFirst = kModelSpecificStart;

// The settings' ranges and meanings are spectron/settings.h's.
CommonBlockModel dyna_common_block() {
  CommonBlockModel m;
  m.dual_axis = false;
  m.angle_x_description =
      "the angle: (raw_counts - zero_counts) / counts_per_degree, after the mounting";
  m.command = settings::command;
  m.baud_code = settings::baud_code;
  m.bus_address = settings::bus_address;
  return m;
}

void add_inputs(std::vector<Point>& points) {
  points.push_back(input_point("raw_counts", kFirst, T::int32, S::raw_counts, "counts",
                               "the sensor reading as the module reports it"));
  Point temperature = input_point("raw_temperature", kFirst + 2, T::int16, S::raw_temperature,
                                  "counts", "the temperature reading as the module reports it");
  temperature.saturate = true;  // a signed 16-bit word on the wire (Modbus-ASCII, A6)
  points.push_back(std::move(temperature));
}

void add_settings(std::vector<Point>& points) {
  const SettingDescriptor own[] = {settings::sensor_offset, settings::temperature_offset,
                                   settings::pwm_offset, settings::eeprom_location,
                                   settings::eeprom_value};
  std::uint16_t address = kFirst;
  for (const SettingDescriptor& setting : own)
    points.push_back(holding_point(address++, T::uint16, setting));
}

}  // namespace

RegisterMap dyna_default_map() {
  std::vector<Point> points = common_block(dyna_common_block());
  add_inputs(points);
  add_settings(points);
  return RegisterMap(std::move(points));
}

}  // namespace tiltgate::spectron
