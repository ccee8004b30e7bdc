// Rieker frames as a listener that only hears the line cuts them (driver/passive_framing.h).
// A frame has no start marker: its DL byte gives its length (docs/protocols.md, "Rieker frame
// layout") and its CRC16 confirms it. Requests and replies share the layout, so a reply is
// told from the next request by its addresses and function (is_reply_to): an unanswered
// request followed by the master's next one is read as two requests, not as a request and
// its reply. Pure.
#pragma once

#include <cstdint>
#include <span>

#include "driver/passive_framing.h"

namespace tiltgate::rieker {

PassiveCut passive_frame(std::span<const std::uint8_t> heard, PassiveRole role,
                         std::span<const std::uint8_t> request);

}  // namespace tiltgate::rieker
