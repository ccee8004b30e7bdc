// Register encoding of every data type in every word and byte order, compared with bytes
// worked out by hand (float bit patterns from IEEE 754: Python's struct.pack('>d', -123.456)
// is c05edd2f1a9fbe77), and the integer rules: rounding, saturation, NaN.
#include "mapping/value_codec.h"

#include <doctest/doctest.h>

#include <cmath>
#include <vector>

using namespace tiltgate;

namespace {

using Words = std::vector<std::uint16_t>;

Words encoded(PointType type, std::size_t words, double value, RegisterOrder order,
              Rounding rounding = Rounding::nearest, double nan_value = 0) {
  Words out(words);
  encode_number(out, type, value, order, rounding, nan_value);
  return out;
}

constexpr auto ABCD = RegisterOrder::abcd;
constexpr auto CDAB = RegisterOrder::cdab;
constexpr auto BADC = RegisterOrder::badc;
constexpr auto DCBA = RegisterOrder::dcba;

}  // namespace

TEST_CASE("float32 in the four orders: 18.44384765625 is 41 93 8D 00") {
  CHECK(encoded(PointType::float32, 2, 18.44384765625, ABCD) == Words{0x4193, 0x8D00});
  CHECK(encoded(PointType::float32, 2, 18.44384765625, CDAB) == Words{0x8D00, 0x4193});
  CHECK(encoded(PointType::float32, 2, 18.44384765625, BADC) == Words{0x9341, 0x008D});
  CHECK(encoded(PointType::float32, 2, 18.44384765625, DCBA) == Words{0x008D, 0x9341});
  for (auto order : {ABCD, CDAB, BADC, DCBA}) {
    const Words w = encoded(PointType::float32, 2, 18.44384765625, order);
    CHECK(decode_number(w, PointType::float32, order) == 18.44384765625);
  }
}

TEST_CASE("float64 in the four orders: -123.456 is C0 5E DD 2F 1A 9F BE 77") {
  CHECK(encoded(PointType::float64, 4, -123.456, ABCD) == Words{0xC05E, 0xDD2F, 0x1A9F, 0xBE77});
  CHECK(encoded(PointType::float64, 4, -123.456, CDAB) == Words{0xBE77, 0x1A9F, 0xDD2F, 0xC05E});
  CHECK(encoded(PointType::float64, 4, -123.456, BADC) == Words{0x5EC0, 0x2FDD, 0x9F1A, 0x77BE});
  CHECK(encoded(PointType::float64, 4, -123.456, DCBA) == Words{0x77BE, 0x9F1A, 0x2FDD, 0x5EC0});
  for (auto order : {ABCD, CDAB, BADC, DCBA}) {
    const Words w = encoded(PointType::float64, 4, -123.456, order);
    CHECK(decode_number(w, PointType::float64, order) == -123.456);
  }
}

TEST_CASE("int32 and uint32 in the four orders") {
  // 16909060 = 0x01020304; -100000 = 0xFFFE7960.
  CHECK(encoded(PointType::uint32, 2, 16909060, ABCD) == Words{0x0102, 0x0304});
  CHECK(encoded(PointType::uint32, 2, 16909060, CDAB) == Words{0x0304, 0x0102});
  CHECK(encoded(PointType::uint32, 2, 16909060, BADC) == Words{0x0201, 0x0403});
  CHECK(encoded(PointType::uint32, 2, 16909060, DCBA) == Words{0x0403, 0x0201});
  CHECK(encoded(PointType::int32, 2, -100000, ABCD) == Words{0xFFFE, 0x7960});
  CHECK(encoded(PointType::int32, 2, -100000, CDAB) == Words{0x7960, 0xFFFE});
  CHECK(encoded(PointType::int32, 2, -100000, BADC) == Words{0xFEFF, 0x6079});
  CHECK(encoded(PointType::int32, 2, -100000, DCBA) == Words{0x6079, 0xFEFF});
  CHECK(decode_number(Words{0x6079, 0xFEFF}, PointType::int32, DCBA) == -100000);
  CHECK(decode_number(Words{0x0304, 0x0102}, PointType::uint32, CDAB) == 16909060);
}

TEST_CASE("16-bit values: only the byte swap counts") {
  CHECK(encoded(PointType::uint16, 1, 0x1234, ABCD) == Words{0x1234});
  CHECK(encoded(PointType::uint16, 1, 0x1234, CDAB) == Words{0x1234});
  CHECK(encoded(PointType::uint16, 1, 0x1234, BADC) == Words{0x3412});
  CHECK(encoded(PointType::uint16, 1, 0x1234, DCBA) == Words{0x3412});
  CHECK(encoded(PointType::int16, 1, -2, ABCD) == Words{0xFFFE});
  CHECK(encoded(PointType::int16, 1, -2, BADC) == Words{0xFEFF});
  CHECK(decode_number(Words{0xFEFF}, PointType::int16, BADC) == -2);
  CHECK(decode_number(Words{0xFFFE}, PointType::uint16, ABCD) == 65534);
}

TEST_CASE("integers round as asked, halves away from zero by default") {
  CHECK(to_integer(2.5, Rounding::nearest, -100, 100, 0) == 3);
  CHECK(to_integer(-2.5, Rounding::nearest, -100, 100, 0) == -3);
  CHECK(to_integer(-2.5, Rounding::floor, -100, 100, 0) == -3);
  CHECK(to_integer(-2.5, Rounding::ceil, -100, 100, 0) == -2);
  CHECK(to_integer(-2.7, Rounding::truncate, -100, 100, 0) == -2);
  CHECK(to_integer(2.7, Rounding::truncate, -100, 100, 0) == 2);
}

TEST_CASE("integers saturate at their type's limits instead of wrapping") {
  CHECK(encoded(PointType::int16, 1, 40000, ABCD) == Words{0x7FFF});
  CHECK(encoded(PointType::int16, 1, -40000, ABCD) == Words{0x8000});
  CHECK(encoded(PointType::uint16, 1, -5, ABCD) == Words{0x0000});
  CHECK(encoded(PointType::uint16, 1, 70000, ABCD) == Words{0xFFFF});
  CHECK(encoded(PointType::uint32, 2, -1, ABCD) == Words{0x0000, 0x0000});
  CHECK(encoded(PointType::uint32, 2, 1e12, ABCD) == Words{0xFFFF, 0xFFFF});
  CHECK(encoded(PointType::int32, 2, 3e9, ABCD) == Words{0x7FFF, 0xFFFF});
  CHECK(encoded(PointType::int32, 2, -3e9, ABCD) == Words{0x8000, 0x0000});
  CHECK(encoded(PointType::int16, 1, INFINITY, ABCD) == Words{0x7FFF});
}

TEST_CASE("NaN reads as the point's nan_value in integers and stays NaN in floats") {
  CHECK(encoded(PointType::int16, 1, NAN, ABCD) == Words{0});
  CHECK(encoded(PointType::int16, 1, NAN, ABCD, Rounding::nearest, -32768) == Words{0x8000});
  CHECK(encoded(PointType::uint16, 1, NAN, ABCD, Rounding::nearest, 65535) == Words{0xFFFF});
  CHECK(std::isnan(
      decode_number(encoded(PointType::float32, 2, NAN, CDAB), PointType::float32, CDAB)));
  CHECK(std::isnan(
      decode_number(encoded(PointType::float64, 4, NAN, ABCD), PointType::float64, ABCD)));
}

TEST_CASE("the server word order maps to ABCD (big) and CDAB (little)") {
  CHECK(register_order(WordOrder::big) == ABCD);
  CHECK(register_order(WordOrder::little) == CDAB);
  std::uint16_t words[2];
  put_uint32(words, 0x00011170, WordOrder::little);
  CHECK(words[0] == 0x1170);
  CHECK(words[1] == 0x0001);
  CHECK(get_uint32(words, WordOrder::little) == 0x00011170);
}
