#include "rieker/passive_framer.h"

#include "rieker/bytes.h"
#include "rieker/codec.h"
#include "rieker/crc16.h"

namespace tiltgate::rieker {
namespace {

// Whether `frame` (CRC unchecked) is addressed as the reply to `request`: its header is read
// even when its CRC fails, so a corrupted reply still shows as that request's reply.
bool passive_answers(std::span<const std::uint8_t> frame, std::span<const std::uint8_t> request) {
  auto asked = decode(request);
  if (!asked) return true;  // a request heard corrupted: any frame may be its reply
  const Frame header{get_u16(&frame[0]), get_u16(&frame[2]), get_u16(&frame[4]), {}};
  return is_reply_to(header, *asked);
}

}  // namespace

PassiveCut passive_frame(std::span<const std::uint8_t> heard, PassiveRole role,
                         std::span<const std::uint8_t> request) {
  if (heard.size() < kHeaderSize) return PassiveCut::need_more();
  const std::size_t length = kMinFrameSize + heard[kHeaderSize - 1];
  if (heard.size() < length) return PassiveCut::need_more();
  const auto frame = heard.first(length);
  if (role == PassiveRole::reply && !request.empty() && !passive_answers(frame, request))
    return PassiveCut::not_a_start();
  const std::size_t crc_at = length - kCrcSize;
  const bool intact = crc16(frame.first(crc_at)) == get_u16(&frame[crc_at]);
  return PassiveCut::whole(length, intact, intact ? "CRC ok" : "bad CRC");
}

}  // namespace tiltgate::rieker
