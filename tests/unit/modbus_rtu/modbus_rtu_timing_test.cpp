// RTU character framing and the t3.5 / t1.5 silences (Serial Line 2.5.1, 2.5.1.1).
#include <doctest/doctest.h>

#include "modbus_rtu/timing.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;
using std::chrono::microseconds;

TEST_CASE("RTU characters are 11 bits with parity or two stop bits, 10 for 8N1") {
  CHECK(bits_per_character(Parity::even, 1) == 11);
  CHECK(bits_per_character(Parity::odd, 1) == 11);
  CHECK(bits_per_character(Parity::none, 2) == 11);
  CHECK(bits_per_character(Parity::none, 1) == 10);
}

TEST_CASE("RTU parity defaults to even, and without parity two stop bits keep 11 bits") {
  CHECK(from_name(parity_names(), "even") == Parity::even);
  CHECK(from_name(parity_names(), "odd") == Parity::odd);
  CHECK(from_name(parity_names(), "none") == Parity::none);
  CHECK_FALSE(from_name(parity_names(), "mark").has_value());
  CHECK(Parity{} == Parity::even);
  CHECK(default_stop_bits(Parity::even) == 1);
  CHECK(default_stop_bits(Parity::none) == 2);
}

TEST_CASE("RTU silences up to 19200 baud are 3.5 and 1.5 character times, rounded up") {
  // 9600 8E1: a character is 11 / 9600 s = 1145.83 us.
  const RtuTiming slow = rtu_timing(9600, 11);
  CHECK(slow.character == microseconds(1146));
  CHECK(slow.frame_gap == microseconds(4011));  // 4010.42
  CHECK(slow.char_gap == microseconds(1719));   // 1718.75
  // 19200 is still computed: 572.92 us a character.
  const RtuTiming at_limit = rtu_timing(19200, 11);
  CHECK(at_limit.character == microseconds(573));
  CHECK(at_limit.frame_gap == microseconds(2006));  // 2005.21
  CHECK(at_limit.char_gap == microseconds(860));    // 859.38
  // 8N1 at 19200: 10 bits.
  CHECK(rtu_timing(19200, 10).frame_gap == microseconds(1823));  // 1822.92
  // 1200 baud: 9166.67 us a character.
  CHECK(rtu_timing(1200, 11).frame_gap == microseconds(32084));  // 32083.33
}

TEST_CASE("RTU silences above 19200 baud are fixed at 1750 us and 750 us") {
  for (std::uint32_t baud : {38400u, 57600u, 115200u, 19201u}) {
    CAPTURE(baud);
    const RtuTiming fast = rtu_timing(baud, 11);
    CHECK(fast.frame_gap == microseconds(1750));
    CHECK(fast.char_gap == microseconds(750));
  }
  CHECK(rtu_timing(38400, 11).character == microseconds(287));  // 286.46
}
