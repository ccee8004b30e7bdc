#include "mapping/point.h"

namespace tiltgate {

const char* to_string(RegisterTable table) {
  switch (table) {
    case RegisterTable::coil: return "coil";
    case RegisterTable::discrete: return "discrete";
    case RegisterTable::input: return "input";
    case RegisterTable::holding: return "holding";
  }
  return "?";
}

const char* to_string(PointType type) {
  switch (type) {
    case PointType::boolean: return "bool";
    case PointType::uint16: return "uint16";
    case PointType::int16: return "int16";
    case PointType::uint32: return "uint32";
    case PointType::float32: return "float32";
    case PointType::string: return "string";
  }
  return "?";
}

const char* to_string(ValueSource source) {
  switch (source) {
    case ValueSource::angle_x: return "angle_x";
    case ValueSource::angle_y: return "angle_y";
    case ValueSource::angle_x_cdeg: return "angle_x_cdeg";
    case ValueSource::angle_y_cdeg: return "angle_y_cdeg";
    case ValueSource::raw_counts: return "raw_counts";
    case ValueSource::raw_temperature: return "raw_temperature";
    case ValueSource::status: return "status";
    case ValueSource::online: return "online";
    case ValueSource::age_ms: return "age_ms";
    case ValueSource::polls_ok: return "polls_ok";
    case ValueSource::polls_failed: return "polls_failed";
    case ValueSource::last_nak: return "last_nak";
    case ValueSource::lock_level: return "lock_level";
    case ValueSource::bus_address: return "bus_address";
    case ValueSource::sample_seq: return "sample_seq";
    case ValueSource::serial: return "serial";
    case ValueSource::firmware: return "firmware";
    case ValueSource::written: return "written";
  }
  return "?";
}

bool is_measurement(ValueSource source) {
  switch (source) {
    case ValueSource::angle_x:
    case ValueSource::angle_y:
    case ValueSource::angle_x_cdeg:
    case ValueSource::angle_y_cdeg:
    case ValueSource::raw_counts:
    case ValueSource::raw_temperature:
      return true;
    default:
      return false;
  }
}

std::uint16_t Point::words() const {
  switch (type) {
    case PointType::boolean:
    case PointType::uint16:
    case PointType::int16: return 1;
    case PointType::uint32:
    case PointType::float32: return 2;
    case PointType::string: return std::uint16_t((chars + 1) / 2);
  }
  return 1;
}

}  // namespace tiltgate
