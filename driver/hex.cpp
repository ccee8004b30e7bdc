#include "driver/hex.h"

namespace tiltgate {

std::string hex_bytes(std::span<const std::uint8_t> bytes) {
  static constexpr char kDigits[] = "0123456789ABCDEF";
  std::string text;
  text.reserve(bytes.size() * 3);
  for (std::uint8_t byte : bytes) {
    if (!text.empty()) text.push_back(' ');
    text.push_back(kDigits[byte >> 4]);
    text.push_back(kDigits[byte & 0x0F]);
  }
  return text;
}

namespace {

int digit_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

bool is_separator(char c) { return c == ' ' || c == '\t' || c == ',' || c == ':' || c == '-'; }

}  // namespace

std::optional<std::vector<std::uint8_t>> parse_hex_bytes(std::string_view text) {
  std::vector<std::uint8_t> bytes;
  std::size_t i = 0;
  while (i < text.size()) {
    if (is_separator(text[i])) {
      ++i;
      continue;
    }
    // A group of digits up to the next separator, with an optional 0x.
    std::size_t end = i;
    while (end < text.size() && !is_separator(text[end])) ++end;
    std::string_view group = text.substr(i, end - i);
    if (group.size() > 2 && group[0] == '0' && (group[1] == 'x' || group[1] == 'X'))
      group.remove_prefix(2);
    if (group.size() % 2 != 0) return std::nullopt;
    for (std::size_t d = 0; d < group.size(); d += 2) {
      const int high = digit_value(group[d]);
      const int low = digit_value(group[d + 1]);
      if (high < 0 || low < 0) return std::nullopt;
      bytes.push_back(std::uint8_t(high * 16 + low));
    }
    i = end;
  }
  return bytes;
}

}  // namespace tiltgate
