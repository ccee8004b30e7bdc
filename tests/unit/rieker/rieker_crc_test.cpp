#include <doctest/doctest.h>

#include <random>

#include "rieker/crc16.h"
#include "unit/rieker/rieker_test_vectors.h"

using tiltgate::rieker::crc16;
using tiltgate::rieker::test::hex;

namespace {

// The definition, bit by bit: CRC-16/ARC (0x8005 reflected, init 0, no final xor).
std::uint16_t crc16_bitwise(const std::vector<std::uint8_t>& bytes) {
  std::uint16_t crc = 0;
  for (std::uint8_t b : bytes) {
    crc ^= b;
    for (int bit = 0; bit < 8; ++bit) {
      crc = (crc & 1) ? static_cast<std::uint16_t>((crc >> 1) ^ 0xA001) : crc >> 1;
    }
  }
  return crc;
}

}  // namespace

TEST_CASE("Rieker CRC16 reproduces the manual's check values") {
  CHECK(crc16(hex("00")) == 0x0000);
  CHECK(crc16(hex("FF")) == 0x4040);
  CHECK(crc16(hex("ABCD")) == 0xA5BE);
  CHECK(crc16(hex("123456")) == 0xFB36);
  CHECK(crc16(hex("9876543210")) == 0xE86E);
}

TEST_CASE("Rieker CRC16 of nothing is the initial value") { CHECK(crc16({}) == 0x0000); }

TEST_CASE("Rieker CRC16 is the standard CRC-16/ARC") {
  // The catalogue check value of CRC-16/ARC over "123456789".
  CHECK(crc16(tiltgate::rieker::test::ascii("123456789")) == 0xBB3D);
}

TEST_CASE("table-driven Rieker CRC16 equals the bitwise definition on random inputs") {
  std::mt19937 rng(20240501);
  std::uniform_int_distribution<int> length(0, 300);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(length(rng)));
    for (auto& b : bytes) b = static_cast<std::uint8_t>(byte(rng));
    REQUIRE(crc16(bytes) == crc16_bitwise(bytes));
  }
}

TEST_CASE("a verified frame's CRC covers DEST through DATA and is sent high byte first") {
  const auto frame = hex("0065 0000 0002 02 00DF F727");
  CHECK(crc16(std::span(frame).first(frame.size() - 2)) == 0xF727);
}
