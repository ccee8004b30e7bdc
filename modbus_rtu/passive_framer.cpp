#include "modbus_rtu/passive_framer.h"

#include "modbus_rtu/codec.h"
#include "modbus_rtu/crc.h"
#include "modbus_rtu/frame_length.h"

namespace tiltgate::modbus_rtu {
namespace {

constexpr std::size_t kPassiveMinFrame = 4;  // address, function, CRC

// Whether a frame of `role` may start with these address and function bytes (the function
// unknown while only the address has arrived), as RtuFrameParser's plausible starts.
bool passive_start(std::span<const std::uint8_t> heard, PassiveRole role,
                   std::span<const std::uint8_t> request) {
  const std::uint8_t address = heard[0];
  const bool has_function = heard.size() > 1;
  const std::uint8_t function = has_function ? heard[1] : 0;
  if (role == PassiveRole::reply && request.size() >= 2) {
    if (request[0] == 0) return false;  // a broadcast is not answered
    return address == request[0] &&
           (!has_function || function == request[1] || function == (request[1] | kExceptionBit));
  }
  if (address > kMaxSlaveAddress) return false;
  if (role == PassiveRole::request) return !has_function || (function >= 1 && function < 0x80);
  return !has_function || function != 0;
}

// A frame of a function the length rule does not know: up to the first CRC that matches.
PassiveCut passive_frame_by_crc(std::span<const std::uint8_t> heard) {
  std::uint16_t crc = kCrcInitial;
  for (std::size_t end = 0; end < heard.size() && end < kMaxFrameSize; ++end) {
    crc = crc16_update(crc, heard[end]);
    if (end + 1 >= kPassiveMinFrame && crc == 0) return PassiveCut::whole(end + 1, true, "CRC ok");
  }
  return heard.size() >= kMaxFrameSize ? PassiveCut::not_a_start() : PassiveCut::need_more();
}

}  // namespace

PassiveCut passive_frame(std::span<const std::uint8_t> heard, PassiveRole role,
                         std::span<const std::uint8_t> request) {
  if (heard.empty()) return PassiveCut::need_more();
  if (!passive_start(heard, role, request)) return PassiveCut::not_a_start();
  const auto kind = role == PassiveRole::request ? FrameKind::request : FrameKind::reply;
  const auto length = frame_length(kind, heard);
  if (!length) return PassiveCut::need_more();
  if (*length == kLengthByCrc) return passive_frame_by_crc(heard);
  if (*length > kMaxFrameSize) return PassiveCut::not_a_start();  // a count no frame can hold
  if (heard.size() < *length) return PassiveCut::need_more();
  const bool intact = crc_ok(heard.first(*length));
  return PassiveCut::whole(*length, intact, intact ? "CRC ok" : "bad CRC");
}

}  // namespace tiltgate::modbus_rtu
