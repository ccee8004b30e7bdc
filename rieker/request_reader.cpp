#include "rieker/request_reader.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "rieker/codec.h"

namespace tiltgate::rieker {

namespace {

bool only_reads(std::uint16_t function) {
  switch (Function(function)) {
    case Function::get_address:
    case Function::check_address:
    case Function::get_angle:
    case Function::get_firmware:
    case Function::get_lock_level:
    case Function::get_serial:
    case Function::change_lock:  // the lock level a change needs: the change itself is recorded
      return true;
    default:
      return false;
  }
}

}  // namespace

std::optional<CarriedRequest> read_request(std::span<const std::uint8_t> request) {
  const auto frame = decode(request);
  if (!frame) return std::nullopt;
  const char* name = function_name(frame->function);
  CarriedRequest carried;
  carried.address = frame->dest;
  carried.may_change = !only_reads(frame->function);
  carried.function =
      fmt::format("function {}{}", frame->function, name ? fmt::format(" ({})", name) : "");
  carried.data = fmt::format("{:02X}", fmt::join(frame->data, ""));
  return carried;
}

std::optional<std::string> read_reply(std::span<const std::uint8_t> request,
                                      std::span<const std::uint8_t> reply) {
  const auto asked = decode(request);
  const auto answer = decode(reply);
  if (!asked || !answer || !is_reply_to(*answer, *asked)) return std::nullopt;
  switch (Function(answer->function)) {
    case Function::ack:
      return std::string("ack");
    case Function::get_angle: {
      if (asked->data.size() != 1 || asked->data[0] < 1 || asked->data[0] > 4) return std::nullopt;
      const auto angles = parse_angle_reply(*answer, AngleType(asked->data[0]));
      if (!angles) return std::nullopt;
      std::string text;
      if (angles->x) text = fmt::format("x {} deg", *angles->x);
      if (angles->y) text += fmt::format("{}y {} deg", text.empty() ? "" : ", ", *angles->y);
      return text;
    }
    case Function::get_address:
      if (const auto address = parse_address_reply(*answer)) return fmt::format("address {}", *address);
      return std::nullopt;
    case Function::get_firmware:
      if (const auto firmware = parse_firmware_reply(*answer))
        return fmt::format("firmware \"{}\"", *firmware);
      return std::nullopt;
    case Function::get_lock_level:
      if (const auto level = parse_lock_level_reply(*answer))
        return fmt::format("lock level {}", int(*level));
      return std::nullopt;
    case Function::get_serial:
      if (const auto serial = parse_serial_reply(*answer)) return fmt::format("serial \"{}\"", *serial);
      return std::nullopt;
    default:
      return std::nullopt;
  }
}

std::optional<std::string> read_refusal(std::span<const std::uint8_t> reply) {
  const auto frame = decode(reply);
  if (!frame || frame->function != std::uint16_t(Function::nak)) return std::nullopt;
  return fmt::format("nak 0x{:02X}", frame->data.size() == 1 ? frame->data[0] : 0xFF);
}

}  // namespace tiltgate::rieker
