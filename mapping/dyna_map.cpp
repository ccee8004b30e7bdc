#include "mapping/dyna_map.h"

#include <vector>

#include "mapping/default_maps.h"

namespace tiltgate {
namespace {

using T = PointType;
using S = ValueSource;
using W = WriteTarget;

// First input register of the block every model shares (status, age, counters, identity,
// tilt, alarms).
constexpr std::uint16_t kStatusBlock = 6;

// The status block and the discrete inputs, taken from the single-axis Rieker map so that the
// two families cannot drift apart. Two of its registers have nothing to show on a Dyna and
// read as "none": last_nak (the Dyna has no NAKs) and lock_level (nor locks).
void add_shared_points(std::vector<Point>& points) {
  const RegisterMap rieker = default_map("h4360");
  for (Point p : rieker.points()) {
    const bool status_block = p.table == RegisterTable::input && p.address >= kStatusBlock;
    if (!status_block && p.table != RegisterTable::discrete) continue;
    // Registers 21..24 hold 8 characters; a Rieker firmware text has 7, a Dyna's is free
    // text (9-bit "F") or "HH.LL" (Modbus-ASCII). Function 43 reports it in full.
    if (p.source == S::firmware) {
      p.chars = 8;
      p.description = "firmware revision, first 8 characters, space padded";
    }
    points.push_back(std::move(p));
  }
}

}  // namespace

RegisterMap dyna_default_map() {
  std::vector<Point> points;
  points.push_back(
      input_point("angle_x", 0, T::float32, S::angle_x, "deg",
                  "the angle: (raw_counts - zero_counts) / counts_per_degree, after the "
                  "mounting"));
  points.push_back(input_point("raw_counts", 2, T::int32, S::raw_counts, "counts",
                               "the sensor reading as the module reports it"));
  points.push_back(input_point("angle_x_cdeg", 4, T::int16, S::angle_x_cdeg, "0.01 deg",
                               "the angle in hundredths of a degree, saturating"));
  Point temperature = input_point("raw_temperature", 5, T::int16, S::raw_temperature, "counts",
                                  "the temperature reading as the module reports it");
  temperature.saturate = true;  // a signed 16-bit word on the wire (Modbus-ASCII, A6)
  points.push_back(std::move(temperature));
  add_shared_points(points);

  // EEPROM words ("Memory Map", spectron/eeprom_map.h): offsets are raw 16-bit words; module
  // addresses 0..255 on a 9-bit bus and 1..250 on Modbus-ASCII, baud codes 7, 10, 15, 32, 64
  // only, and EEPROM locations the even 2..22 and 100..280 (the driver checks those exactly).
  points.push_back(holding_point("sensor_offset", 0, T::uint16, W::sensor_offset, 0, 65535, "",
                                 "EEPROM 6, offset for the sensor (subtracted by the module)"));
  points.push_back(holding_point("temperature_offset", 1, T::uint16, W::temperature_offset, 0,
                                 65535, "", "EEPROM 10, offset for the temperature sensor"));
  points.push_back(holding_point("pwm_offset", 2, T::uint16, W::pwm_offset, 0, 65535, "",
                                 "EEPROM 20, offset for the PWM output"));
  points.push_back(holding_point("eeprom_location", 3, T::uint16, W::eeprom_location, 2, 280, "",
                                 "EEPROM window: the location eeprom_value writes go to"));
  points.push_back(holding_point("eeprom_value", 4, T::uint16, W::eeprom_value, 0, 65535, "",
                                 "EEPROM window: written to the selected location"));
  points.push_back(
      holding_point("command", 5, T::uint16, W::command, 1, 1, "", "1 resets the module"));
  points.push_back(holding_point("baud_code", 6, T::uint16, W::baud_code, 7, 64, "",
                                 "EEPROM 22: 7 38400, 10 28800, 15 19200, 32 9600, 64 4800; takes "
                                 "effect after a reset"));
  points.push_back(holding_point("rs485_address", 7, T::uint16, W::bus_address, 0, 255, "",
                                 "EEPROM 16, module address; the gateway follows the module"));
  return RegisterMap(std::move(points));
}

}  // namespace tiltgate
