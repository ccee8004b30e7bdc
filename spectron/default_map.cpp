#include "spectron/default_map.h"

#include <vector>

#include "mapping/common_block.h"
#include "spectron/setting_ids.h"

namespace tiltgate::spectron {
namespace {

using T = PointType;
using S = ValueSource;
using W = WriteTarget;

constexpr std::uint16_t kFirst = kModelSpecificStart;

// EEPROM words ("Memory Map", spectron/eeprom_map.h): offsets are raw 16-bit words; module
// addresses 0..255 on a 9-bit bus and 1..250 on Modbus-ASCII, baud codes 7, 10, 15, 32, 64
// only, and EEPROM locations the even 2..22 and 100..280 (the driver checks those exactly).
CommonBlockModel dyna_common_block() {
  CommonBlockModel m;
  m.dual_axis = false;
  m.angle_x_description =
      "the angle: (raw_counts - zero_counts) / counts_per_degree, after the mounting";
  m.command = {1, 1, "1 resets the module"};
  m.baud_code = {7, 64,
                 "EEPROM 22: 7 38400, 10 28800, 15 19200, 32 9600, 64 4800; takes effect after "
                 "a reset"};
  m.rs485_address = {0, 255, "EEPROM 16, module address; the gateway follows the module"};
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
  points.push_back(holding_point("sensor_offset", kFirst, T::uint16, setting::sensor_offset, 0, 65535,
                                 "", "EEPROM 6, offset for the sensor (subtracted by the module)"));
  points.push_back(holding_point("temperature_offset", kFirst + 1, T::uint16,
                                 setting::temperature_offset, 0, 65535, "",
                                 "EEPROM 10, offset for the temperature sensor"));
  points.push_back(holding_point("pwm_offset", kFirst + 2, T::uint16, setting::pwm_offset, 0, 65535,
                                 "", "EEPROM 20, offset for the PWM output"));
  points.push_back(holding_point("eeprom_location", kFirst + 3, T::uint16, setting::eeprom_location, 2,
                                 280, "",
                                 "EEPROM window: selects a location and reads it from the module"));
  points.push_back(holding_point("eeprom_value", kFirst + 4, T::uint16, setting::eeprom_value, 0, 65535,
                                 "", "EEPROM window: the selected location as read back; a "
                                     "write writes it"));
}

}  // namespace

RegisterMap dyna_default_map() {
  std::vector<Point> points = common_block(dyna_common_block());
  add_inputs(points);
  add_settings(points);
  return RegisterMap(std::move(points));
}

}  // namespace tiltgate::spectron
