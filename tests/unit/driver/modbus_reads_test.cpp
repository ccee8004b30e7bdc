// Which passed-through requests only read (driver/modbus_reads.h): those may pass while
// [server] writes is false; 08 by its sub-function.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "driver/modbus_reads.h"

using namespace tiltgate;

TEST_CASE("08 reads for its echo, its diagnostic register and its counts, and changes for the rest") {
  using Pdu = std::vector<std::uint8_t>;
  CHECK(reads_only(Pdu{0x08, 0x00, 0x00, 0x12, 0x34}));  // return query data
  CHECK(reads_only(Pdu{0x08, 0x00, 0x02, 0x00, 0x00}));  // return diagnostic register
  for (std::uint8_t sub = 0x0B; sub <= 0x12; ++sub) {
    CAPTURE(int(sub));
    CHECK(reads_only(Pdu{0x08, 0x00, sub, 0x00, 0x00}));
  }
  CHECK_FALSE(reads_only(Pdu{0x08, 0x00, 0x01, 0x00, 0x00}));  // restart communications
  CHECK_FALSE(reads_only(Pdu{0x08, 0x00, 0x04, 0x00, 0x00}));  // force listen only
  CHECK_FALSE(reads_only(Pdu{0x08, 0x00, 0x0A, 0x00, 0x00}));  // clear counters
  CHECK_FALSE(reads_only(Pdu{0x08, 0x00, 0x14, 0x00, 0x00}));  // clear overrun counter
  CHECK_FALSE(reads_only(Pdu{0x08, 0x00}));                    // too short to tell
  CHECK(reads_only(Pdu{0x0B}));
  CHECK(reads_only(Pdu{0x03, 0x00, 0x00, 0x00, 0x01}));
  CHECK_FALSE(reads_only(Pdu{0x06, 0x00, 0x00, 0x00, 0x01}));
}
