// The store's files as they lie in its directory (docs/northbound.md, "The store"): a segment's
// name and header, and the `cursor` file's bytes. Pure; used by the store as it opens
// (record_store_open.cpp) and as it works (record_store.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "store/crc32.h"

namespace tiltgate::store {

// The first bytes of every segment file: a file of the store, in this format.
inline constexpr std::array<std::uint8_t, 8> kSegmentMagic = {'t', 'g', 's', 't',
                                                              'o', 'r', 'e', '1'};
inline constexpr std::uint64_t kSegmentHeaderBytes = kSegmentMagic.size();
// A segment's name: its id in twenty digits, ".seg".
inline constexpr std::size_t kIdDigits = 20;
// The cursor file: a magic, the segment id and offset the replay has reached, their CRC-32.
inline constexpr std::array<std::uint8_t, 8> kCursorMagic = {'t', 'g', 'c', 'u',
                                                             'r', 's', 'o', 'r'};
inline constexpr std::size_t kCursorBytes = 8 + 8 + 8 + 4;
inline constexpr const char* kCursorName = "cursor";

// The id in a segment file's name, none for any other file.
inline std::optional<std::uint64_t> segment_id(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  if (name.size() != kIdDigits + 4 || name.substr(kIdDigits) != ".seg") return std::nullopt;
  std::uint64_t id = 0;
  for (std::size_t i = 0; i < kIdDigits; ++i) {
    if (name[i] < '0' || name[i] > '9') return std::nullopt;
    id = id * 10 + static_cast<std::uint64_t>(name[i] - '0');
  }
  return id;
}

// Where the replay stands: the next record to replay is at `offset` in segment `id`.
struct Cursor {
  std::uint64_t id = 0;
  std::uint64_t offset = 0;
};

inline std::vector<std::uint8_t> cursor_bytes(const Cursor& cursor) {
  std::vector<std::uint8_t> bytes(kCursorMagic.begin(), kCursorMagic.end());
  for (const std::uint64_t v : {cursor.id, cursor.offset})
    for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  const std::uint32_t crc = crc32(bytes);
  for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(crc >> (8 * i)));
  return bytes;
}

// None for bytes that are not a whole, valid cursor.
inline std::optional<Cursor> parse_cursor(std::span<const std::uint8_t> bytes) {
  if (bytes.size() != kCursorBytes ||
      !std::equal(kCursorMagic.begin(), kCursorMagic.end(), bytes.begin()))
    return std::nullopt;
  const auto le = [&](std::size_t at, int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(bytes[at + i]) << (8 * i);
    return v;
  };
  if (crc32(bytes.first(24)) != static_cast<std::uint32_t>(le(24, 4))) return std::nullopt;
  return Cursor{le(8, 8), le(16, 8)};
}

// "1 record", "3 records": for the log.
inline std::string records_text(std::uint64_t n) {
  return std::to_string(n) + (n == 1 ? " record" : " records");
}

}  // namespace tiltgate::store
