#include "rieker/codec.h"

#include <array>
#include <cassert>

#include "rieker/bytes.h"
#include "rieker/crc16.h"

namespace tiltgate::rieker {

const char* function_name(std::uint16_t function) {
  switch (static_cast<Function>(function)) {
    case Function::ack: return "ACK";
    case Function::nak: return "NAK";
    case Function::set_address: return "set address";
    case Function::get_address: return "get address";
    case Function::check_address: return "check address";
    case Function::get_angle: return "get angle";
    case Function::change_lock: return "change lock";
    case Function::restart: return "restart";
    case Function::set_zero_to_value: return "set zero to value";
    case Function::set_zero_to_angle: return "set zero to current angle";
    case Function::get_firmware: return "get firmware revision";
    case Function::get_lock_level: return "get lock level";
    case Function::get_serial: return "get serial number";
    case Function::set_baud: return "set baud";
    case Function::set_filter: return "set filter response";
  }
  return nullptr;
}

bool needs_unlock(Function function) {
  switch (function) {
    case Function::set_address:
    case Function::restart:
    case Function::set_zero_to_value:
    case Function::set_zero_to_angle:
    case Function::set_baud:
    case Function::set_filter:
      return true;
    default:
      return false;
  }
}

const char* nak_name(std::uint8_t code) {
  switch (code) {
    case 0: return "CRC failure";
    case 1: return "unknown function";
    case 2: return "function not valid for this sensor or mode";
    case 3: return "data invalid";
    case 4: return "wrong lock level";
    case 5: return "busy";
    default: return "unknown NAK code";
  }
}

namespace {
// "Set Baud" type code table; index = code - 1.
constexpr std::array<std::uint32_t, 8> kBaudByCode = {9600,   38400,  115200, 125000,
                                                      128000, 250000, 19200,  62500};
}  // namespace

std::optional<std::uint32_t> baud_for_code(int code) {
  if (code < 1 || code > static_cast<int>(kBaudByCode.size())) return std::nullopt;
  return kBaudByCode[static_cast<std::size_t>(code - 1)];
}

std::optional<int> code_for_baud(std::uint32_t baud) {
  for (std::size_t i = 0; i < kBaudByCode.size(); ++i) {
    if (kBaudByCode[i] == baud) return static_cast<int>(i + 1);
  }
  return std::nullopt;
}

const char* to_string(DecodeError error) {
  switch (error) {
    case DecodeError::too_short: return "frame too short";
    case DecodeError::length_mismatch: return "frame length does not match DL";
    case DecodeError::bad_crc: return "bad CRC";
  }
  return "unknown decode error";
}

std::vector<std::uint8_t> encode(const Frame& frame) {
  assert(frame.data.size() <= kMaxDataSize);
  std::vector<std::uint8_t> out;
  out.reserve(kMinFrameSize + frame.data.size());
  put_u16(out, frame.dest);
  put_u16(out, frame.src);
  put_u16(out, frame.function);
  out.push_back(static_cast<std::uint8_t>(frame.data.size()));
  out.insert(out.end(), frame.data.begin(), frame.data.end());
  put_u16(out, crc16(out));
  return out;
}

Expected<Frame, DecodeError> decode(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kMinFrameSize) return Unexpected(DecodeError::too_short);
  const std::size_t data_length = bytes[kHeaderSize - 1];
  if (bytes.size() != kMinFrameSize + data_length) return Unexpected(DecodeError::length_mismatch);
  const std::size_t crc_at = kHeaderSize + data_length;
  if (crc16(bytes.first(crc_at)) != get_u16(&bytes[crc_at])) return Unexpected(DecodeError::bad_crc);
  Frame frame;
  frame.dest = get_u16(&bytes[0]);
  frame.src = get_u16(&bytes[2]);
  frame.function = get_u16(&bytes[4]);
  frame.data.assign(bytes.begin() + kHeaderSize, bytes.begin() + static_cast<std::ptrdiff_t>(crc_at));
  return frame;
}

bool is_reply_to(const Frame& reply, const Frame& request) {
  if (reply.dest != request.src) return false;
  if (request.dest != kBroadcastAddress && reply.src != request.dest) return false;
  // A sensor answers a query with the query's own function, or with ACK or NAK.
  return reply.function == request.function ||
         reply.function == std::uint16_t(Function::ack) ||
         reply.function == std::uint16_t(Function::nak);
}

const char* model_name(Model model) { return model == Model::h6 ? "h6" : "h4360"; }
std::optional<Model> model_from_name(std::string_view name) {
  if (name == "h6") return Model::h6;
  if (name == "h4360") return Model::h4360;
  return std::nullopt;
}

}  // namespace tiltgate::rieker
