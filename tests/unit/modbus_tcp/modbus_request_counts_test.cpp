// Modbus TCP requests counted by function and by exception, from the replies sent.
#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "modbus_tcp/modbus_request_counts.h"

using namespace tiltgate;

namespace {
// MBAP header (transaction 1, protocol 0, length, unit 1), then the PDU.
std::vector<std::uint8_t> reply(std::vector<std::uint8_t> pdu) {
  pdu.insert(pdu.begin(), {0, 1, 0, 0, 0, std::uint8_t(pdu.size() + 1), 1});
  return pdu;
}
}  // namespace

TEST_CASE("Modbus request counts: by function, exceptions by function and code") {
  ModbusRequestCounts counts;
  counts.note_reply(reply({0x04, 0x02, 0x00, 0x01}));
  counts.note_reply(reply({0x04, 0x02, 0x00, 0x02}));
  counts.note_reply(reply({0x83, 0x02}));
  counts.note_reply(reply({0x83, 0x02}));
  counts.note_reply(reply({0x90, 0x01}));
  const auto requests = counts.requests();
  REQUIRE(requests.size() == 3);
  CHECK(requests[0].function == 0x03);
  CHECK(requests[0].count == 2);
  CHECK(requests[1].function == 0x04);
  CHECK(requests[1].count == 2);
  CHECK(requests[2].function == 0x10);
  CHECK(requests[2].count == 1);
  const auto exceptions = counts.exceptions();
  REQUIRE(exceptions.size() == 2);
  CHECK(exceptions[0].function == 0x03);
  CHECK(exceptions[0].exception == 0x02);
  CHECK(exceptions[0].count == 2);
  CHECK(exceptions[1].function == 0x10);
  CHECK(exceptions[1].exception == 0x01);
}

TEST_CASE("Modbus request counts: a reply too short to have a function is not counted") {
  ModbusRequestCounts counts;
  counts.note_reply(std::vector<std::uint8_t>{0, 1, 0, 0, 0, 1, 1});
  CHECK(counts.requests().empty());
}
