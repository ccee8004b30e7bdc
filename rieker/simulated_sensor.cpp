#include "rieker/simulated_sensor.h"

#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include "rieker/bytes.h"

namespace tiltgate::rieker {
namespace {

// DATA length of each query, from the function descriptions ("Length:").
std::size_t request_data_length(Function function) {
  switch (function) {
    case Function::set_address: return 2;
    case Function::get_angle:
    case Function::set_zero_to_angle:
    case Function::set_baud:
    case Function::set_filter: return 1;
    case Function::change_lock:
    case Function::set_zero_to_value: return 5;
    default: return 0;
  }
}

std::size_t axis_index(Axis axis) { return axis == Axis::y ? 1 : 0; }

}  // namespace



SimulatedSensor::SimulatedSensor(SimulatedSensorOptions options)
    : options_(std::move(options)),
      address_(options_.address),
      filter_(options_.filter),
      baud_code_(options_.baud_code) {}

std::optional<Frame> SimulatedSensor::handle(const Frame& request, SimTime now) {
  if (!addressed(request.dest)) return std::nullopt;
  const auto function = static_cast<Function>(request.function);
  // "ACK"/"NAK": "Not a query, no response".
  if (function == Function::ack || function == Function::nak) return std::nullopt;
  ++requests_handled_;
  ++requests_by_function_[request.function];
  if (faults_.silent > 0) {
    --faults_.silent;
    return std::nullopt;
  }
  if (faults_.busy > 0) {
    --faults_.busy;
    return nak(request, NakCode::busy);
  }
  auto own = faults_.by_function.find(function);
  if (own != faults_.by_function.end()) {
    if (own->second.silent > 0) {
      --own->second.silent;
      return std::nullopt;
    }
    if (own->second.nak > 0) {
      --own->second.nak;
      return nak(request, own->second.nak_code);
    }
  }
  return answer(request, now);
}

std::chrono::milliseconds SimulatedSensor::reply_delay(std::uint16_t function) const {
  auto own = faults_.by_function.find(static_cast<Function>(function));
  const auto extra = own == faults_.by_function.end() ? std::chrono::milliseconds{0}
                                                      : own->second.delay;
  return faults_.reply_delay + extra;
}

std::uint64_t SimulatedSensor::requests_of(Function function) const {
  auto found = requests_by_function_.find(static_cast<std::uint16_t>(function));
  return found == requests_by_function_.end() ? 0 : found->second;
}

std::optional<std::vector<std::uint8_t>> SimulatedSensor::respond(const Frame& request,
                                                                  SimTime now) {
  auto reply = handle(request, now);
  if (!reply) return std::nullopt;
  std::vector<std::uint8_t> bytes = encode(*reply);
  if (faults_.corrupt_crc > 0) {
    --faults_.corrupt_crc;
    bytes.back() ^= 0xFF;
  }
  if (faults_.garbage > 0) {
    --faults_.garbage;
    bytes.insert(bytes.begin(), faults_.garbage_bytes.begin(), faults_.garbage_bytes.end());
  }
  return bytes;
}

std::optional<Frame> SimulatedSensor::handle_crc_failure(const Frame& damaged) {
  if (!addressed(damaged.dest)) return std::nullopt;
  ++requests_handled_;
  return nak(damaged, NakCode::crc_failure);
}

void SimulatedSensor::restart() {
  lock_ = LockLevel::locked;
  temporary_zero_[0].reset();
  temporary_zero_[1].reset();
  if (pending_baud_code_) baud_code_ = *std::exchange(pending_baud_code_, std::nullopt);
  ++restarts_;
}

double SimulatedSensor::raw_angle(Axis axis, SimTime now) const {
  const double phase = 2.0 * std::numbers::pi * now.count() / options_.sway_period_s;
  return axis == Axis::x ? options_.angle_x + options_.sway_amplitude * std::sin(phase)
                         : options_.angle_y + options_.sway_amplitude * std::cos(phase);
}

double SimulatedSensor::zero_offset(Axis axis) const {
  const std::size_t i = axis_index(axis);
  return temporary_zero_[i].value_or(permanent_zero_[i]);
}

double SimulatedSensor::angle_x(SimTime now) const {
  return raw_angle(Axis::x, now) - zero_offset(Axis::x);
}

double SimulatedSensor::angle_y(SimTime now) const {
  return raw_angle(Axis::y, now) - zero_offset(Axis::y);
}

void SimulatedSensor::set_angles(double x, double y) {
  options_.angle_x = x;
  options_.angle_y = y;
  options_.sway_amplitude = 0.0;
}

void SimulatedSensor::set_motion(double amplitude, double period_s) {
  options_.sway_amplitude = amplitude;
  options_.sway_period_s = period_s;
}

bool SimulatedSensor::addressed(std::uint16_t dest) const {
  return dest == address_ || dest == kBroadcastAddress;
}

std::optional<Frame> SimulatedSensor::answer(const Frame& request, SimTime now) {
  const auto function = static_cast<Function>(request.function);
  if (!function_name(request.function)) return nak(request, NakCode::unknown_function);
  if (needs_unlock(function) && lock_ != LockLevel::unlocked) {
    return nak(request, NakCode::wrong_lock_level);
  }
  if (request.data.size() != request_data_length(function)) {
    return nak(request, NakCode::data_invalid);
  }
  switch (function) {
    case Function::get_address: return make_address_reply(request.src, address_);
    case Function::check_address: return ack(request);
    case Function::get_angle: return answer_get_angle(request, now);
    case Function::change_lock: return answer_change_lock(request);
    case Function::restart: {
      Frame reply = ack(request);  // "ACK before resetting"
      restart();
      return reply;
    }
    case Function::set_zero_to_value: return answer_set_zero_to_value(request);
    case Function::set_zero_to_angle: return answer_set_zero_to_angle(request, now);
    case Function::get_firmware: return make_firmware_reply(request.src, address_, firmware());
    case Function::get_lock_level: return make_lock_level_reply(request.src, address_, lock_);
    case Function::get_serial: return make_serial_reply(request.src, address_, serial());
    case Function::set_address:
    case Function::set_baud:
    case Function::set_filter: return answer_setting(request);
    case Function::ack:
    case Function::nak: break;  // filtered out by handle()
  }
  return std::nullopt;
}

Frame SimulatedSensor::answer_get_angle(const Frame& request, SimTime now) const {
  const std::uint8_t type = request.data[0];
  if (type < 1 || type > 4) return nak(request, NakCode::data_invalid);
  const bool single_axis_type = type == static_cast<std::uint8_t>(AngleType::single_axis);
  if (single_axis_type != (options_.model == Model::h4360)) {
    return nak(request, NakCode::not_valid_for_sensor);
  }
  const float x = static_cast<float>(angle_x(now));
  const float y = static_cast<float>(angle_y(now));
  switch (static_cast<AngleType>(type)) {
    case AngleType::single_axis:
    case AngleType::x: return make_angle_reply(request.src, address_, std::array{x});
    case AngleType::y: return make_angle_reply(request.src, address_, std::array{y});
    case AngleType::x_and_y: break;
  }
  return make_angle_reply(request.src, address_, std::array{x, y});
}

Frame SimulatedSensor::answer_change_lock(const Frame& request) {
  const std::uint8_t level = request.data[0];
  if (level > 1 || get_u32(&request.data[1]) != kLockPassword) {
    return nak(request, NakCode::data_invalid);
  }
  lock_ = static_cast<LockLevel>(level);
  return ack(request);
}

Frame SimulatedSensor::answer_set_zero_to_value(const Frame& request) {
  const std::uint8_t axis = request.data[0];
  const float offset = get_f32(&request.data[1]);
  if ((axis != 1 && axis != 2) || !std::isfinite(offset)) {
    return nak(request, NakCode::data_invalid);
  }
  if (axis == 2 && options_.model == Model::h4360) {
    return nak(request, NakCode::not_valid_for_sensor);
  }
  const std::size_t i = axis_index(static_cast<Axis>(axis));
  permanent_zero_[i] = offset;
  temporary_zero_[i].reset();
  return ack(request);
}

Frame SimulatedSensor::answer_set_zero_to_angle(const Frame& request, SimTime now) {
  const std::uint8_t type = request.data[0];
  if (type > 1) return nak(request, NakCode::data_invalid);
  // "Takes both axis angle measurements": the raw angles become the offsets.
  for (Axis axis : {Axis::x, Axis::y}) {
    const std::size_t i = axis_index(axis);
    if (static_cast<ZeroPersistence>(type) == ZeroPersistence::temporary) {
      temporary_zero_[i] = raw_angle(axis, now);
    } else {
      permanent_zero_[i] = raw_angle(axis, now);
      temporary_zero_[i].reset();
    }
  }
  return ack(request);
}

Frame SimulatedSensor::answer_setting(const Frame& request) {
  const Frame reply = ack(request);  // from the address the request reached
  switch (static_cast<Function>(request.function)) {
    case Function::set_address: {
      const std::uint16_t address = get_u16(request.data.data());
      if (address < kMinSensorAddress || address > kMaxSensorAddress) break;
      address_ = address;
      return reply;
    }
    case Function::set_baud:
      if (!baud_for_code(request.data[0])) break;
      pending_baud_code_ = request.data[0];  // "restart ... is required" to switch
      return reply;
    case Function::set_filter:
      if (request.data[0] < kMinFilter || request.data[0] > kMaxFilter) break;
      filter_ = request.data[0];
      return reply;
    default: break;
  }
  return nak(request, NakCode::data_invalid);
}

Frame SimulatedSensor::ack(const Frame& request) const { return make_ack(request.src, address_); }

Frame SimulatedSensor::nak(const Frame& request, NakCode code) const {
  return make_nak(request.src, address_, code);
}

}  // namespace tiltgate::rieker
