// The name a misspelt one most likely meant, for "did you mean" in error messages: config
// keys, map-file source and setting names.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace tiltgate {

// The known name a misspelt one most likely meant: within edit distance 2, or a prefix either
// way ("baudrate" -> "baud", "timeout" -> "timeout_ms"). Empty when nothing is close.
std::string closest_name(std::string_view unknown, std::span<const std::string> known);

}  // namespace tiltgate
