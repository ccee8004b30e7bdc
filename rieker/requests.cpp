// Typed requests: each builder checks its arguments, then lays out DATA as the manual's
// function descriptions give it (every multi-byte value big-endian).
#include <cmath>
#include <string>

#include "rieker/bytes.h"
#include "rieker/codec.h"

namespace tiltgate::rieker {
namespace {

Unexpected<ArgumentError> bad_argument(std::string message) {
  return Unexpected(ArgumentError{std::move(message)});
}

bool is_sensor_address(std::int64_t a) { return a >= kMinSensorAddress && a <= kMaxSensorAddress; }

RequestResult request(Route route, Function function, std::vector<std::uint8_t> data = {}) {
  if (!is_sensor_address(route.sensor) && route.sensor != kBroadcastAddress) {
    return bad_argument("sensor address " + std::to_string(route.sensor) +
                        " is outside 1..65000 and not the broadcast address 0xFFFC");
  }
  if (route.master > kMaxMasterAddress) {
    return bad_argument("master address " + std::to_string(route.master) +
                        " is outside 0..65500");
  }
  if (route.master == route.sensor) {
    return bad_argument("master and sensor share address " + std::to_string(route.master));
  }
  return Frame{route.sensor, route.master, static_cast<std::uint16_t>(function), std::move(data)};
}

template <class Code>
std::uint8_t code_byte(Code code) {
  return static_cast<std::uint8_t>(code);
}

}  // namespace

RequestResult set_address_request(Route route, std::int64_t new_address) {
  if (!is_sensor_address(new_address)) {
    return bad_argument("new sensor address " + std::to_string(new_address) +
                        " is outside 1..65000");
  }
  std::vector<std::uint8_t> data;
  put_u16(data, static_cast<std::uint16_t>(new_address));
  return request(route, Function::set_address, std::move(data));
}

RequestResult get_address_request(Route route) { return request(route, Function::get_address); }

RequestResult check_address_request(Route route) {
  return request(route, Function::check_address);
}

RequestResult get_angle_request(Route route, AngleType type) {
  const int code = code_byte(type);
  if (code < 1 || code > 4) {
    return bad_argument("angle type code " + std::to_string(code) + " is outside 1..4");
  }
  return request(route, Function::get_angle, {code_byte(type)});
}

RequestResult change_lock_request(Route route, LockLevel level, std::uint32_t password) {
  if (level != LockLevel::locked && level != LockLevel::unlocked) {
    return bad_argument("lock level " + std::to_string(code_byte(level)) + " is not 0 or 1");
  }
  std::vector<std::uint8_t> data{code_byte(level)};
  put_u32(data, password);
  return request(route, Function::change_lock, std::move(data));
}

RequestResult restart_request(Route route) { return request(route, Function::restart); }

RequestResult set_zero_to_value_request(Route route, Axis axis, float offset_degrees) {
  if (axis != Axis::x && axis != Axis::y) {
    return bad_argument("axis code " + std::to_string(code_byte(axis)) + " is not 1 (X) or 2 (Y)");
  }
  if (!std::isfinite(offset_degrees) || std::fabs(offset_degrees) > 360.0f) {
    return bad_argument("zero offset " + std::to_string(offset_degrees) +
                        " is not a finite angle within +-360 degrees");
  }
  std::vector<std::uint8_t> data{code_byte(axis)};
  put_f32(data, offset_degrees);
  return request(route, Function::set_zero_to_value, std::move(data));
}

RequestResult set_zero_to_angle_request(Route route, ZeroPersistence persistence) {
  if (persistence != ZeroPersistence::temporary && persistence != ZeroPersistence::permanent) {
    return bad_argument("zero type code " + std::to_string(code_byte(persistence)) +
                        " is not 0 (temporary) or 1 (permanent)");
  }
  return request(route, Function::set_zero_to_angle, {code_byte(persistence)});
}

RequestResult get_firmware_request(Route route) { return request(route, Function::get_firmware); }

RequestResult get_lock_level_request(Route route) {
  return request(route, Function::get_lock_level);
}

RequestResult get_serial_request(Route route) { return request(route, Function::get_serial); }

RequestResult set_baud_request(Route route, int baud_code) {
  if (!baud_for_code(baud_code)) {
    return bad_argument("baud code " + std::to_string(baud_code) + " is outside 1..8");
  }
  return request(route, Function::set_baud, {static_cast<std::uint8_t>(baud_code)});
}

RequestResult set_filter_request(Route route, int filter_response) {
  if (filter_response < kMinFilter || filter_response > kMaxFilter) {
    return bad_argument("filter response " + std::to_string(filter_response) +
                        " is outside 1..6");
  }
  return request(route, Function::set_filter, {static_cast<std::uint8_t>(filter_response)});
}

}  // namespace tiltgate::rieker
