// Dyna frames as a listener that only hears the line cuts them (driver/passive_framing.h), one
// framer per protocol. Pure.
//
// Modbus-ASCII style: ':' to CR LF, the LRC checked over the characters as heard (A8); a reply
// comes from the module the request addressed, for its command (is_reply_to).
//
// 9-bit addressing: a listener cannot see the ninth bit. Without PARMRK (and the parity
// checks that go with it) a receive-only port delivers the address byte like any other, so
// frames are told by their form instead: a request is one byte (taken as the address,
// whatever its value), a command the module understands (parse_nine_bit_body) and CR LF; a
// reply is one line of printable text and CR LF (A5), and for a read (3, A, C) one decimal
// number (A4). Neither has a checksum: a frame is whole when its CR LF arrives ("CR LF, no
// checksum"). What this cannot tell apart: docs/diagnostics.md, "Listening only".
#pragma once

#include <cstdint>
#include <span>

#include "driver/passive_framing.h"

namespace tiltgate::spectron {

PassiveCut ascii_passive_frame(std::span<const std::uint8_t> heard, PassiveRole role,
                               std::span<const std::uint8_t> request);

PassiveCut nine_bit_passive_frame(std::span<const std::uint8_t> heard, PassiveRole role,
                                  std::span<const std::uint8_t> request);

}  // namespace tiltgate::spectron
