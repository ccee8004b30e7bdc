// CRC-16/MODBUS: the catalogue check value, real frames from the spec and common tools, and
// the table-driven implementation against the spec's bit-by-bit algorithm.
#include <doctest/doctest.h>

#include <random>
#include <string_view>

#include "modbus_rtu/crc.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

using namespace tiltgate::modbus_rtu;
using test::hex;

TEST_CASE("Modbus CRC of \"123456789\" is the catalogue check value 0x4B37") {
  const std::string_view text = "123456789";
  const std::vector<std::uint8_t> bytes(text.begin(), text.end());
  CHECK(crc16(bytes) == 0x4B37);
  CHECK(test::reference_crc(bytes) == 0x4B37);
}

TEST_CASE("Modbus CRC of real frames is sent low byte first") {
  // Read 10 holding registers from slave 1.
  const auto read_10 = hex("01 03 00 00 00 0A C5 CD");
  CHECK(crc16(std::span(read_10).first(6)) == 0xCDC5);
  CHECK(crc_ok(read_10));
  // The spec's example (Application Protocol 6.3): slave 17 reads 3 registers from 107.
  const auto spec_example = hex("11 03 00 6B 00 03 76 87");
  CHECK(crc16(std::span(spec_example).first(6)) == 0x8776);
  CHECK(crc_ok(spec_example));

  std::vector<std::uint8_t> built = hex("11 03 00 6B 00 03");
  append_crc(built);
  CHECK(built == spec_example);
}

TEST_CASE("Modbus CRC check rejects a changed byte, swapped CRC bytes and short frames") {
  auto frame = hex("01 03 00 00 00 0A C5 CD");
  frame[3] ^= 0x01;
  CHECK_FALSE(crc_ok(frame));
  CHECK_FALSE(crc_ok(hex("01 03 00 00 00 0A CD C5")));  // high byte first: wrong
  CHECK_FALSE(crc_ok(hex("01 03 00")));
}

TEST_CASE("Modbus CRC over a frame with its CRC appended is 0") {
  const auto frame = hex("11 03 06 AE 41 56 52 43 40 49 AD");
  CHECK(crc16(frame) == 0);
  std::uint16_t running = kCrcInitial;
  for (std::uint8_t b : frame) running = crc16_update(running, b);
  CHECK(running == 0);
}

TEST_CASE("Modbus CRC table matches the spec's bit-by-bit algorithm on random data") {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255), length(0, 300);
  for (int round = 0; round < 200; ++round) {
    std::vector<std::uint8_t> data(static_cast<std::size_t>(length(rng)));
    for (auto& b : data) b = static_cast<std::uint8_t>(byte(rng));
    REQUIRE(crc16(data) == test::reference_crc(data));
  }
}
