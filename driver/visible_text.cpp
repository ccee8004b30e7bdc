#include "driver/visible_text.h"

#include <cstdint>
#include <fmt/format.h>

namespace tiltgate {

namespace {

// The length of the well-formed UTF-8 sequence starting at `text[at]` (RFC 3629: no overlong
// forms, no surrogates, nothing past U+10FFFF) and its code point; 0 when it is not one.
std::size_t utf8_sequence(std::string_view text, std::size_t at, char32_t& code) {
  const auto byte = [&](std::size_t i) { return std::uint8_t(text[at + i]); };
  const std::uint8_t lead = byte(0);
  std::size_t length = 0;
  char32_t min = 0;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2, code = lead & 0x1F, min = 0x80;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3, code = lead & 0x0F, min = 0x800;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4, code = lead & 0x07, min = 0x10000;
  } else {
    return 0;
  }
  if (at + length > text.size()) return 0;
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i) & 0x3F);
  }
  if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return length;
}

}  // namespace

std::string visible_text(std::string_view untrusted) {
  std::string shown;
  shown.reserve(untrusted.size());
  for (std::size_t at = 0; at < untrusted.size();) {
    const auto c = std::uint8_t(untrusted[at]);
    if (c >= 0x20 && c < 0x7F) {
      if (c == '\\') shown += '\\';
      shown += char(c);
      ++at;
      continue;
    }
    switch (c) {
      case '\n': shown += "\\n"; ++at; continue;
      case '\r': shown += "\\r"; ++at; continue;
      case '\t': shown += "\\t"; ++at; continue;
      default: break;
    }
    char32_t code = 0;
    const std::size_t length = c < 0x80 ? 0 : utf8_sequence(untrusted, at, code);
    if (length == 0) {  // a C0 control, DEL, or a byte of no well-formed sequence
      shown += fmt::format("\\x{:02X}", c);
      ++at;
    } else if ((code >= 0x80 && code <= 0x9F) || code == 0x2028 || code == 0x2029) {
      shown += fmt::format("\\u{:04X}", std::uint32_t(code));
      at += length;
    } else {
      shown.append(untrusted.substr(at, length));
      at += length;
    }
  }
  return shown;
}

}  // namespace tiltgate
