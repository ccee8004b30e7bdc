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

std::optional<std::string> read_refusal(std::span<const std::uint8_t> reply) {
  const auto frame = decode(reply);
  if (!frame || frame->function != std::uint16_t(Function::nak)) return std::nullopt;
  return fmt::format("nak 0x{:02X}", frame->data.size() == 1 ? frame->data[0] : 0xFF);
}

}  // namespace tiltgate::rieker
