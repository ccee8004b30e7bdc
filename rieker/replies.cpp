// Typed replies: what the master makes of a sensor's frame, and (for the simulator) how a
// sensor builds one. A reply is addressed to the request's SRC and sent from the sensor's own
// address, also when the request was a broadcast ("Get Address" example).
#include <string>

#include "rieker/bytes.h"
#include "rieker/codec.h"

namespace tiltgate::rieker {
namespace {

Unexpected<ReplyError> reply_error(ReplyError::Kind kind, const Frame& reply) {
  ReplyError error;
  error.kind = kind;
  error.function = reply.function;
  error.data_length = reply.data.size();
  if (kind == ReplyError::Kind::nak && !reply.data.empty()) error.nak_code = reply.data[0];
  return Unexpected(error);
}

// The common checks: a NAK becomes its error, another function is unexpected, and DATA must be
// exactly `data_length` bytes long.
std::optional<Unexpected<ReplyError>> check_shape(const Frame& reply, Function expected,
                                                  std::size_t data_length) {
  if (reply.function == static_cast<std::uint16_t>(Function::nak)) {
    // "NAK": one byte of error code.
    return reply_error(reply.data.size() == 1 ? ReplyError::Kind::nak
                                              : ReplyError::Kind::wrong_length,
                       reply);
  }
  if (reply.function != static_cast<std::uint16_t>(expected)) {
    return reply_error(ReplyError::Kind::unexpected_function, reply);
  }
  if (reply.data.size() != data_length) return reply_error(ReplyError::Kind::wrong_length, reply);
  return std::nullopt;
}

std::string text_of(const Frame& reply) { return std::string(reply.data.begin(), reply.data.end()); }

Frame text_reply(std::uint16_t to, std::uint16_t from, Function function, std::string_view text,
                 std::size_t width) {
  std::vector<std::uint8_t> data(width, ' ');
  for (std::size_t i = 0; i < width && i < text.size(); ++i) {
    data[i] = static_cast<std::uint8_t>(text[i]);
  }
  return Frame{to, from, static_cast<std::uint16_t>(function), std::move(data)};
}

}  // namespace

std::string describe(const ReplyError& error) {
  const char* name = function_name(error.function);
  const std::string function = name ? name : "function " + std::to_string(error.function);
  switch (error.kind) {
    case ReplyError::Kind::nak:
      return "NAK " + std::to_string(error.nak_code) + " (" + nak_name(error.nak_code) + ")";
    case ReplyError::Kind::unexpected_function:
      return "unexpected reply: " + function;
    case ReplyError::Kind::wrong_length:
      return "reply " + function + " has the wrong length (" +
             std::to_string(error.data_length) + " data bytes)";
    case ReplyError::Kind::bad_data:
      return "reply " + function + " holds a value the protocol does not define";
  }
  return "unknown reply error";
}

ReplyResult<Done> parse_ack(const Frame& reply) {
  if (auto error = check_shape(reply, Function::ack, 0)) return *error;
  return Done{};
}

ReplyResult<std::uint16_t> parse_address_reply(const Frame& reply) {
  if (auto error = check_shape(reply, Function::get_address, 2)) return *error;
  return get_u16(reply.data.data());
}

ReplyResult<Angles> parse_angle_reply(const Frame& reply, AngleType requested) {
  const bool both = requested == AngleType::x_and_y;
  if (auto error = check_shape(reply, Function::get_angle, both ? 8 : 4)) return *error;
  const float first = get_f32(reply.data.data());
  Angles angles;
  switch (requested) {
    case AngleType::single_axis:
    case AngleType::x: angles.x = first; break;
    case AngleType::y: angles.y = first; break;
    case AngleType::x_and_y:
      angles.x = first;
      angles.y = get_f32(reply.data.data() + 4);
      break;
  }
  return angles;
}

ReplyResult<std::string> parse_firmware_reply(const Frame& reply) {
  if (auto error = check_shape(reply, Function::get_firmware, kFirmwareSize)) return *error;
  return text_of(reply);
}

ReplyResult<LockLevel> parse_lock_level_reply(const Frame& reply) {
  if (auto error = check_shape(reply, Function::get_lock_level, 1)) return *error;
  if (reply.data[0] > 1) return reply_error(ReplyError::Kind::bad_data, reply);
  return static_cast<LockLevel>(reply.data[0]);
}

ReplyResult<std::string> parse_serial_reply(const Frame& reply) {
  if (auto error = check_shape(reply, Function::get_serial, kSerialSize)) return *error;
  std::string serial = text_of(reply);
  serial.erase(serial.find_last_not_of(std::string_view(" \0", 2)) + 1);
  return serial;
}

Frame make_ack(std::uint16_t to, std::uint16_t from) {
  return Frame{to, from, static_cast<std::uint16_t>(Function::ack), {}};
}

Frame make_nak(std::uint16_t to, std::uint16_t from, NakCode code) {
  return Frame{to, from, static_cast<std::uint16_t>(Function::nak),
               {static_cast<std::uint8_t>(code)}};
}

Frame make_address_reply(std::uint16_t to, std::uint16_t from) {
  std::vector<std::uint8_t> data;
  put_u16(data, from);
  return Frame{to, from, static_cast<std::uint16_t>(Function::get_address), std::move(data)};
}

Frame make_angle_reply(std::uint16_t to, std::uint16_t from, std::span<const float> angles) {
  std::vector<std::uint8_t> data;
  for (float angle : angles) put_f32(data, angle);
  return Frame{to, from, static_cast<std::uint16_t>(Function::get_angle), std::move(data)};
}

Frame make_lock_level_reply(std::uint16_t to, std::uint16_t from, LockLevel level) {
  return Frame{to, from, static_cast<std::uint16_t>(Function::get_lock_level),
               {static_cast<std::uint8_t>(level)}};
}

Frame make_firmware_reply(std::uint16_t to, std::uint16_t from, std::string_view firmware) {
  return text_reply(to, from, Function::get_firmware, firmware, kFirmwareSize);
}

Frame make_serial_reply(std::uint16_t to, std::uint16_t from, std::string_view serial) {
  return text_reply(to, from, Function::get_serial, serial, kSerialSize);
}

}  // namespace tiltgate::rieker
