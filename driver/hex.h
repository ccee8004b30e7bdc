// Bytes as the trace log and the commissioning commands show them: two upper-case hex digits
// each, separated by single spaces ("01 03 00 00 00 0A C5 CD"), the way the vendors' manuals
// and their PC tools print frames. One formatter for every family, so lines compare at a glance.
#pragma once

#include <cstdint>
#include <span>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace tiltgate {

std::string hex_bytes(std::span<const std::uint8_t> bytes);

// The bytes of hex text as an engineer types it: "01 03 00 0A", "01030A", "0x01,0x03"; none when
// it holds anything else or an odd digit.
std::optional<std::vector<std::uint8_t>> parse_hex_bytes(std::string_view text);

}  // namespace tiltgate
