// A register-map point: one named value at a fixed place in one Modbus table of one unit.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "driver/sensor_driver.h"

namespace tiltgate {

enum class RegisterTable : std::uint8_t { coil, discrete, input, holding };

const char* to_string(RegisterTable table);

enum class PointType : std::uint8_t { boolean, uint16, int16, uint32, float32, string };

const char* to_string(PointType type);

// What a point shows. Every value a driver's SensorState offers, plus values the gateway derives.
enum class ValueSource : std::uint8_t {
  angle_x,          // degrees
  angle_y,
  angle_x_cdeg,     // hundredths of a degree
  angle_y_cdeg,
  raw_counts,
  raw_temperature,
  status,           // bit 0 online, 1 stale, 2 last write failed, 3 identity unknown
  online,           // status bit 0 as a bit
  age_ms,
  polls_ok,
  polls_failed,
  last_nak,         // 65535 when none
  lock_level,
  bus_address,
  sample_seq,
  serial,
  firmware,
  written,          // holding registers: the last value written through the gateway
};

const char* to_string(ValueSource source);

// Whether reading the point needs a fresh measurement (0x0B while the sensor is offline or
// stale) or is diagnostic and always readable, so a PLC can see why the data is missing.
bool is_measurement(ValueSource source);

struct Point {
  std::string name;
  RegisterTable table = RegisterTable::input;
  std::uint16_t address = 0;      // 0-based protocol address
  PointType type = PointType::uint16;
  std::uint16_t chars = 0;        // strings: characters (two per register)
  ValueSource source = ValueSource::written;
  std::optional<WriteTarget> write;  // holding points that trigger a sensor write
  double min = 0, max = 0;        // writable points: allowed range (inclusive)
  std::string units;
  std::string description;

  std::uint16_t words() const;    // registers (or bits) the point occupies
  std::uint32_t end() const { return std::uint32_t(address) + words(); }
};

}  // namespace tiltgate
