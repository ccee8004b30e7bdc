#include "config/sparkplug_id.h"

#include <array>
#include <cstdint>

namespace tiltgate::sparkplug {
namespace {

// Well-formed UTF-8 (RFC 3629): no overlong forms, no surrogates, nothing above U+10FFFF.
bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto b = static_cast<std::uint8_t>(s[i]);
    std::size_t extra = 0;
    std::uint32_t code = 0;
    if (b < 0x80) {
      ++i;
      continue;
    } else if ((b & 0xE0) == 0xC0) {
      extra = 1;
      code = b & 0x1F;
    } else if ((b & 0xF0) == 0xE0) {
      extra = 2;
      code = b & 0x0F;
    } else if ((b & 0xF8) == 0xF0) {
      extra = 3;
      code = b & 0x07;
    } else {
      return false;
    }
    if (i + extra >= s.size()) return false;  // the sequence is cut short
    for (std::size_t k = 1; k <= extra; ++k) {
      const auto c = static_cast<std::uint8_t>(s[i + k]);
      if ((c & 0xC0) != 0x80) return false;
      code = (code << 6) | (c & 0x3F);
    }
    constexpr std::array<std::uint32_t, 4> kSmallest = {0, 0x80, 0x800, 0x10000};
    if (code < kSmallest[extra] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) {
      return false;
    }
    i += extra + 1;
  }
  return true;
}

}  // namespace

std::optional<std::string> check_id(std::string_view what, std::string_view id) {
  const std::string name(what);
  if (id.empty()) return name + " is empty";
  if (id.find_first_of("+#/") != std::string_view::npos) {
    return name + " \"" + std::string(id) + "\" has '+', '#' or '/', which Sparkplug reserves";
  }
  if (id.find('\0') != std::string_view::npos) return name + " has a NUL character";
  if (!valid_utf8(id)) return name + " is not valid UTF-8";
  return std::nullopt;
}

}  // namespace tiltgate::sparkplug
