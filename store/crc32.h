// CRC-32 as zlib, PNG and Ethernet compute it (IEEE 802.3: polynomial 0x04C11DB7, reflected,
// initial value and final XOR 0xFFFFFFFF; check value of "123456789" 0xCBF43926): zlib's own
// crc32(), under a name that takes a span. The store's check on every record; pure.
#pragma once

#include <cstdint>
#include <span>

namespace tiltgate::store {

// The CRC of `bytes`, or of everything before them and then `bytes` when `crc` is the CRC of
// what came before: crc32(b, crc32(a)) == crc32(a followed by b).
std::uint32_t crc32(std::span<const std::uint8_t> bytes, std::uint32_t crc = 0);

}  // namespace tiltgate::store
