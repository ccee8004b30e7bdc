#include "store/crc32.h"

#include <zlib.h>

#include <algorithm>
#include <limits>

namespace tiltgate::store {

std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc) {
  // zlib takes a uInt length: longer spans go in pieces, which chain like whole ones.
  uLong value = crc;
  while (!bytes.empty()) {
    const std::size_t piece = std::min<std::size_t>(bytes.size(), std::numeric_limits<uInt>::max());
    value = ::crc32(value, bytes.data(), static_cast<uInt>(piece));
    bytes = bytes.subspan(piece);
  }
  return static_cast<std::uint32_t>(value);
}

}  // namespace tiltgate::store
