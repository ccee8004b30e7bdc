// The Dyna memory map: which locations exist, which the gateway may write, with which values.
#include <doctest/doctest.h>

#include "spectron/eeprom_map.h"

using namespace tiltgate::spectron;
using namespace tiltgate::spectron::eeprom;

namespace {

std::string refusal(std::int64_t location, std::int64_t value, Protocol protocol) {
  const auto checked = check_value(location, value, protocol);
  REQUIRE_FALSE(checked.has_value());
  return checked.error();
}

}  // namespace

TEST_CASE("the map lists the even locations 2..22 and the reserved block 100..280") {
  for (std::int64_t location = 2; location <= 22; location += 2) CHECK(is_documented(location));
  for (std::int64_t location = 100; location <= 280; location += 2) CHECK(is_documented(location));
  for (std::int64_t location : {-2, 0, 1, 3, 23, 24, 34, 98, 101, 282, 65535}) {
    CAPTURE(location);
    CHECK_FALSE(is_documented(location));
  }
  CHECK(location_name(4) == std::string("serial number"));
  CHECK(location_name(16) == std::string("module address"));
  CHECK(location_name(22) == std::string("baud rate code"));
  CHECK(location_name(14) == std::string("reserved"));
  CHECK(location_name(200) == std::string("reserved"));
  CHECK(location_name(24) == nullptr);
}

TEST_CASE("only the offsets, the module address and the baud code are writable") {
  for (std::int64_t location = 0; location <= 300; ++location) {
    const bool expected = location == 6 || location == 10 || location == 16 || location == 20 ||
                          location == 22;
    CAPTURE(location);
    CHECK(writable(location) == expected);
  }
  CHECK(refusal(4, 1, Protocol::nine_bit) == "location 4 (serial number) is read-only");
  CHECK(refusal(100, 1, Protocol::nine_bit) == "location 100 (reserved) is read-only");
  CHECK(refusal(7, 1, Protocol::nine_bit) == "EEPROM location 7 is odd; locations are even");
  CHECK(refusal(40, 1, Protocol::nine_bit) ==
        "EEPROM location 40 is not in the memory map (2..22, 100..280)");
}

TEST_CASE("with reserved writes allowed, the even reserved block 100..280 is writable too") {
  for (std::int64_t location = 0; location <= 300; ++location) {
    const bool expected = writable(location) || (location >= 100 && location <= 280 &&
                                                 location % 2 == 0);
    CAPTURE(location);
    CHECK(writable(location, ReservedWrites::allowed) == expected);
  }
  CHECK(check_value(100, 355, Protocol::modbus_ascii, ReservedWrites::allowed).has_value());
  CHECK_FALSE(check_value(101, 355, Protocol::modbus_ascii, ReservedWrites::allowed).has_value());
  CHECK_FALSE(check_value(8, 1, Protocol::modbus_ascii, ReservedWrites::allowed).has_value());
  CHECK_FALSE(check_value(4, 1, Protocol::modbus_ascii, ReservedWrites::allowed).has_value());
}

TEST_CASE("the module address range depends on the protocol") {
  CHECK(check_value(16, 0, Protocol::nine_bit).has_value());
  CHECK(check_value(16, 255, Protocol::nine_bit).has_value());
  CHECK_FALSE(check_value(16, 256, Protocol::nine_bit).has_value());
  CHECK(refusal(16, 0, Protocol::modbus_ascii) ==
        "value 0 for location 16 (module address) is out of range 1..250 on a Modbus-ASCII bus");
  CHECK(check_value(16, 1, Protocol::modbus_ascii).has_value());
  CHECK(check_value(16, 250, Protocol::modbus_ascii).has_value());
  CHECK_FALSE(check_value(16, 251, Protocol::modbus_ascii).has_value());
  CHECK(min_address(Protocol::nine_bit) == 0);
  CHECK(max_address(Protocol::modbus_ascii) == 250);
}

TEST_CASE("the baud code takes only the five documented codes") {
  CHECK(baud_for_code(7) == 38400u);
  CHECK(baud_for_code(10) == 28800u);
  CHECK(baud_for_code(15) == 19200u);
  CHECK(baud_for_code(32) == 9600u);
  CHECK(baud_for_code(64) == 4800u);
  CHECK_FALSE(baud_for_code(8).has_value());
  CHECK(code_for_baud(28800) == 10);
  CHECK_FALSE(code_for_baud(115200).has_value());
  for (int code : {7, 10, 15, 32, 64}) CHECK(check_value(22, code, Protocol::modbus_ascii));
  CHECK(refusal(22, 8, Protocol::nine_bit) ==
        "value 8 for location 22 (baud rate code) is not one of 7, 10, 15, 32, 64");
}

TEST_CASE("offsets take any 16-bit word") {
  for (std::int64_t location : {6, 10, 20}) {
    CHECK(check_value(location, 0, Protocol::nine_bit).has_value());
    CHECK(check_value(location, 65535, Protocol::modbus_ascii).has_value());
    CHECK_FALSE(check_value(location, 65536, Protocol::nine_bit).has_value());
    CHECK_FALSE(check_value(location, -1, Protocol::nine_bit).has_value());
  }
  CHECK(refusal(6, 70000, Protocol::nine_bit) ==
        "value 70000 for location 6 (sensor offset) is out of range 0..65535");
}
