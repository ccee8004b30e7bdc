// Bytes as the trace log and the commissioning commands show them: two upper-case hex digits
// each, separated by single spaces ("01 03 00 00 00 0A C5 CD"), the way the vendors' manuals
// and their PC tools print frames. One formatter for every family, so lines compare at a glance.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace tiltgate {

std::string hex_bytes(std::span<const std::uint8_t> bytes);

}  // namespace tiltgate
