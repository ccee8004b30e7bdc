// The Rieker frames whose CRC was verified by computation
// (docs/protocols.md, "Rieker verified frames"), shared by the codec, sensor and simulator
// tests, and a hex helper to write frames as the manual does.
#pragma once

#include <cctype>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "rieker/codec.h"

namespace tiltgate::rieker::test {

// "0065 0000 0002 02 00DF F727" -> bytes; spaces are ignored.
inline std::vector<std::uint8_t> hex(std::string_view text) {
  std::vector<std::uint8_t> out;
  int high = -1;
  for (char c : text) {
    if (std::isspace(static_cast<unsigned char>(c))) continue;
    const int nibble = std::isdigit(static_cast<unsigned char>(c))
                           ? c - '0'
                           : std::tolower(static_cast<unsigned char>(c)) - 'a' + 10;
    if (high < 0) {
      high = nibble;
    } else {
      out.push_back(static_cast<std::uint8_t>(high << 4 | nibble));
      high = -1;
    }
  }
  return out;
}

inline std::vector<std::uint8_t> ascii(std::string_view text) {
  return std::vector<std::uint8_t>(text.begin(), text.end());
}

struct Vector {
  const char* meaning;
  const char* wire;  // hex, as in docs/protocols.md, "Rieker verified frames"
  Frame frame;
};

inline const std::vector<Vector>& verified_vectors() {
  static const std::vector<Vector> vectors = {
      {"set address of 101 to 223", "0065 0000 0002 02 00DF F727", {0x0065, 0, 2, {0x00, 0xDF}}},
      {"ACK from 101", "0000 0065 0000 00 CC1E", {0, 0x0065, 0, {}}},
      {"get address, broadcast", "FFFC 0000 0003 00 C31B", {0xFFFC, 0, 3, {}}},
      {"reply: address 223", "0000 00DF 0003 02 00DF 73F3", {0, 0x00DF, 3, {0x00, 0xDF}}},
      {"check address 223", "00DF 0000 0004 00 AF11", {0x00DF, 0, 4, {}}},
      {"ACK from 223", "0000 00DF 0000 00 D43B", {0, 0x00DF, 0, {}}},
      {"get X and Y angles from 101", "0065 0000 0005 01 04 5425", {0x0065, 0, 5, {0x04}}},
      {"reply: X and Y angles", "0000 0065 0005 08 BF4B1C00 41938D00 71C8",
       {0, 0x0065, 5, hex("BF4B1C00 41938D00")}},
      {"restart 101", "0065 0000 0010 00 3504", {0x0065, 0, 16, {}}},
      {"set X zero of 101 to 0.0", "0065 0000 0019 05 01 00000000 995A",
       {0x0065, 0, 25, hex("01 00000000")}},
      {"set zero to current angle, permanent", "0065 0000 001A 01 01 91D4",
       {0x0065, 0, 26, {0x01}}},
      {"get firmware revision", "0065 0000 001C 00 3501", {0x0065, 0, 28, {}}},
      {"get lock level", "0065 0000 001E 00 5500", {0x0065, 0, 30, {}}},
      {"reply: lock level 1", "0000 0065 001E 01 01 5EEC", {0, 0x0065, 30, {0x01}}},
      {"get serial number", "0065 0000 0025 00 6513", {0x0065, 0, 37, {}}},
      {"reply: serial 962285", "0000 0065 0025 0A 39363232383520202020 DF6D",
       {0, 0x0065, 37, ascii("962285    ")}},
      {"set filter response of 101 to 2", "0065 0000 0029 01 02 9F64", {0x0065, 0, 41, {0x02}}},
  };
  return vectors;
}

}  // namespace tiltgate::rieker::test
