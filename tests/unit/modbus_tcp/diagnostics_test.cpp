// Functions 08 and 11 as the parser checks them and the formatter answers them
// (modbus_tcp/diagnostics.h): Modbus Application Protocol V1.1b3, sections 6.8 and 6.9, whose
// examples these frames follow.
#include <doctest/doctest.h>

#include <cstdint>
#include <variant>
#include <vector>

#include "modbus_tcp/diagnostics.h"
#include "modbus_tcp/modbus_reply_format.h"
#include "modbus_tcp/modbus_request.h"

using namespace tiltgate;

namespace {

using Bytes = std::vector<std::uint8_t>;

// An ADU (transaction 0x0102, unit 0x11) around `pdu`.
Bytes diagnostics_frame(const Bytes& pdu) {
  const auto length = std::uint16_t(pdu.size() + 1);
  Bytes adu;
  for (std::uint8_t b : {0x01, 0x02, 0x00, 0x00, length >> 8, length & 0xFF, 0x11}) adu.push_back(b);
  for (std::uint8_t b : pdu) adu.push_back(b);
  return adu;
}

ParsedAdu parsed(const Bytes& pdu) { return parse_adu(diagnostics_frame(pdu)); }

ModbusRequest request_of(const Bytes& pdu) {
  ParsedAdu adu = parsed(pdu);
  REQUIRE(std::holds_alternative<ModbusRequest>(adu));
  return std::get<ModbusRequest>(adu);
}

ModbusException refusal_of(const Bytes& pdu) {
  ParsedAdu adu = parsed(pdu);
  REQUIRE(std::holds_alternative<RejectedRequest>(adu));
  return std::get<RejectedRequest>(adu).exception;
}

ModbusResponse with_values(std::vector<std::uint16_t> values) {
  ModbusResponse response;
  response.registers = std::move(values);
  return response;
}

}  // namespace

TEST_CASE("08 0x0000 returns the query data as it came, any length") {
  const ModbusRequest request = request_of({0x08, 0x00, 0x00, 0xA5, 0x37});
  CHECK(request.function == 0x08);
  CHECK(request.diagnostic == 0x0000);
  CHECK_FALSE(request.is_write);
  CHECK(format_reply(request, ModbusResponse{}) == diagnostics_frame({0x08, 0x00, 0x00, 0xA5, 0x37}));
  const ModbusRequest longer = request_of({0x08, 0x00, 0x00, 0x01, 0x02, 0x03, 0x04});
  CHECK(format_reply(longer, ModbusResponse{}) ==
        diagnostics_frame({0x08, 0x00, 0x00, 0x01, 0x02, 0x03, 0x04}));
  CHECK(request_of({0x08, 0x00, 0x00}).diagnostic == 0x0000);  // no data at all
}

TEST_CASE("08 0x000A clears: a write, echoed") {
  const ModbusRequest request = request_of({0x08, 0x00, 0x0A, 0x00, 0x00});
  CHECK(request.is_write);
  CHECK(request.diagnostic == diagnostic::clear_counters);
  CHECK(format_reply(request, ModbusResponse{}) == diagnostics_frame({0x08, 0x00, 0x0A, 0x00, 0x00}));
}

TEST_CASE("08 0x000B..0x0012 return one count each, reads") {
  for (std::uint16_t sub = 0x000B; sub <= 0x0012; ++sub) {
    CAPTURE(sub);
    const ModbusRequest request = request_of({0x08, 0x00, std::uint8_t(sub), 0x00, 0x00});
    CHECK_FALSE(request.is_write);
    CHECK(request.diagnostic == sub);
    CHECK(returns_count(sub));
    CHECK(format_reply(request, with_values({0x0108})) ==
          diagnostics_frame({0x08, 0x00, std::uint8_t(sub), 0x01, 0x08}));
  }
  CHECK_FALSE(returns_count(0x000A));
  CHECK_FALSE(returns_count(0x0013));
}

TEST_CASE("08's malformed requests are 03, the sub-functions not served 01") {
  CHECK(refusal_of({0x08}) == ModbusException::illegal_value);
  CHECK(refusal_of({0x08, 0x00}) == ModbusException::illegal_value);
  CHECK(refusal_of({0x08, 0x00, 0x0B}) == ModbusException::illegal_value);
  CHECK(refusal_of({0x08, 0x00, 0x0B, 0x00, 0x01}) == ModbusException::illegal_value);
  CHECK(refusal_of({0x08, 0x00, 0x0A, 0xFF, 0x00}) == ModbusException::illegal_value);
  CHECK(refusal_of({0x08, 0x00, 0x0E, 0x00, 0x00, 0x00}) == ModbusException::illegal_value);
  CHECK(refusal_of({0x08, 0x00, 0x01, 0x00, 0x00}) == ModbusException::illegal_function);  // restart
  CHECK(refusal_of({0x08, 0x00, 0x04, 0x00, 0x00}) == ModbusException::illegal_function);  // listen only
  CHECK(refusal_of({0x08, 0x00, 0x14, 0x00, 0x00}) == ModbusException::illegal_function);
  CHECK(refusal_of({0x08, 0xFF, 0xFF, 0x00, 0x00}) == ModbusException::illegal_function);
}

TEST_CASE("11 is the function code alone, and its reply is the status word and the event count") {
  const ModbusRequest request = request_of({0x0B});
  CHECK_FALSE(request.is_write);
  CHECK(format_reply(request, with_values({0x0000, 0x0108})) ==
        diagnostics_frame({0x0B, 0x00, 0x00, 0x01, 0x08}));
  CHECK(refusal_of({0x0B, 0x00}) == ModbusException::illegal_value);
}

TEST_CASE("a diagnostics response without its values is 04, never a short reply") {
  const ModbusRequest count = request_of({0x08, 0x00, 0x0E, 0x00, 0x00});
  CHECK(format_reply(count, ModbusResponse{}) == diagnostics_frame({0x88, 0x04}));
  const ModbusRequest events = request_of({0x0B});
  CHECK(format_reply(events, with_values({0x0000})) == diagnostics_frame({0x8B, 0x04}));
  ModbusResponse refused;
  refused.exception = ModbusException::illegal_function;
  CHECK(format_reply(count, refused) == diagnostics_frame({0x88, 0x01}));
}
