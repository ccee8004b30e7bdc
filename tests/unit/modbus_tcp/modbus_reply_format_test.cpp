// The gateway's reply formatter, byte for byte against replies worked out by hand from the
// examples of the Modbus Application Protocol V1.1b3, section 6. (modbus_reply_differential
// _test.cpp compares it with libmodbus over generated requests.)
#include <doctest/doctest.h>

#include <cstdint>
#include <variant>
#include <vector>

#include "modbus_tcp/modbus_reply_format.h"
#include "modbus_tcp/modbus_request.h"

using namespace tiltgate;

namespace {

using Bytes = std::vector<std::uint8_t>;

// MBAP header (transaction 0x1234, protocol 0, unit 0x11) + pdu.
Bytes frame(const Bytes& pdu) {
  const auto length = std::uint16_t(pdu.size() + 1);
  // Built with reserve + push_back: g++ 12 -O2 reports a false array-bounds error for
  // vector::insert after an initializer list here.
  Bytes adu;
  adu.reserve(7 + pdu.size());
  for (std::uint8_t b : {0x12, 0x34, 0x00, 0x00, length >> 8, length & 0xFF, 0x11}) adu.push_back(b);
  for (std::uint8_t b : pdu) adu.push_back(b);
  return adu;
}

ModbusRequest checked(const Bytes& pdu) {
  ParsedAdu parsed = parse_adu(frame(pdu));
  REQUIRE(std::holds_alternative<ModbusRequest>(parsed));
  return std::get<ModbusRequest>(parsed);
}

// Coils as the spec packs them: least significant bit first.
std::vector<bool> bits_of(const Bytes& packed, std::size_t count) {
  std::vector<bool> bits;
  for (std::size_t i = 0; i < count; ++i) bits.push_back((packed[i / 8] >> (i % 8)) & 1);
  return bits;
}

ModbusResponse registers(std::vector<std::uint16_t> values) {
  ModbusResponse response;
  response.registers = std::move(values);
  return response;
}

ModbusResponse bits(std::vector<bool> values) {
  ModbusResponse response;
  response.bits = std::move(values);
  return response;
}

ModbusResponse failure(ModbusException code) {
  ModbusResponse response;
  response.exception = code;
  return response;
}

Bytes encode(const ModbusRequest& request, const ModbusResponse& response) {
  return format_reply(request, response);
}

}  // namespace

TEST_CASE("read replies carry the handler's values as the spec packs them") {
  // 03: registers 108-110 = 022B 0000 0064 (section 6.3).
  CHECK(encode(checked({0x03, 0x00, 0x6B, 0x00, 0x03}),
               registers({0x022B, 0x0000, 0x0064})) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x09, 0x11, 0x03, 0x06, 0x02, 0x2B, 0x00, 0x00,
              0x00, 0x64});
  // 01: coils 20-38 = CD 6B 05 (section 6.1).
  CHECK(encode(checked({0x01, 0x00, 0x13, 0x00, 0x13}),
               bits(bits_of({0xCD, 0x6B, 0x05}, 19))) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x11, 0x01, 0x03, 0xCD, 0x6B, 0x05});
  // 02: inputs 197-218 = AC DB 35 (section 6.2).
  CHECK(encode(checked({0x02, 0x00, 0xC4, 0x00, 0x16}),
               bits(bits_of({0xAC, 0xDB, 0x35}, 22))) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x11, 0x02, 0x03, 0xAC, 0xDB, 0x35});
  // 04: input register 9 = 000A (section 6.4).
  CHECK(encode(checked({0x04, 0x00, 0x08, 0x00, 0x01}), registers({0x000A})) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x05, 0x11, 0x04, 0x02, 0x00, 0x0A});
}

TEST_CASE("reads at the top of the address space are encoded") {
  CHECK(encode(checked({0x03, 0xFF, 0xFF, 0x00, 0x01}), registers({0xBEEF})) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x05, 0x11, 0x03, 0x02, 0xBE, 0xEF});
  std::vector<std::uint16_t> values(125);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = std::uint16_t(i * 257);
  const Bytes reply = encode(checked({0x04, 0xFF, 0x83, 0x00, 0x7D}), registers(values));
  REQUIRE(reply.size() == 9 + 250);
  CHECK(reply[5] == 3 + 250);  // MBAP length: unit, function, byte count, data
  CHECK(reply[8] == 250);
  CHECK(reply[9 + 2 * 124] == 0x7C);  // 124 * 257 = 0x7C7C
  CHECK(reply[9 + 2 * 124 + 1] == 0x7C);
  const Bytes coils = encode(checked({0x01, 0xF8, 0x30, 0x07, 0xD0}),
                             bits(std::vector<bool>(2000, true)));
  REQUIRE(coils.size() == 9 + 250);
  CHECK(coils[8] == 250);
  CHECK(coils.back() == 0xFF);
}

TEST_CASE("write replies echo what the spec says they echo") {
  // 05 and 06 echo the request (sections 6.5, 6.6).
  CHECK(encode(checked({0x05, 0x00, 0xAC, 0xFF, 0x00}), {}) ==
        frame({0x05, 0x00, 0xAC, 0xFF, 0x00}));
  CHECK(encode(checked({0x06, 0x00, 0x01, 0x00, 0x03}), {}) ==
        frame({0x06, 0x00, 0x01, 0x00, 0x03}));
  // 15 and 16 echo address and quantity (sections 6.11, 6.12).
  CHECK(encode(checked({0x0F, 0x00, 0x13, 0x00, 0x0A, 0x02, 0xCD, 0x01}), {}) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x11, 0x0F, 0x00, 0x13, 0x00, 0x0A});
  CHECK(encode(checked({0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02}),
               {}) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x11, 0x10, 0x00, 0x01, 0x00, 0x02});
}

TEST_CASE("a handler's exception becomes the exception reply") {
  CHECK(encode(checked({0x03, 0x00, 0x6B, 0x00, 0x03}),
               failure(ModbusException::illegal_address)) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0x83, 0x02});
  CHECK(encode(checked({0x06, 0x00, 0x01, 0x00, 0x03}),
               failure(ModbusException::gateway_target_failed)) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0x86, 0x0B});
  CHECK(encode(checked({0x01, 0x00, 0x00, 0x00, 0x01}),
               failure(ModbusException::gateway_path_unavailable)) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0x81, 0x0A});
  CHECK(encode(checked({0x10, 0x00, 0x01, 0x00, 0x01, 0x02, 0x00, 0x0A}),
               failure(ModbusException::busy)) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0x90, 0x06});
}

TEST_CASE("a read answered with the wrong number of values is 04") {
  const Bytes device_failure{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0x83, 0x04};
  CHECK(encode(checked({0x03, 0x00, 0x6B, 0x00, 0x03}), registers({1, 2})) ==
        device_failure);
  CHECK(encode(checked({0x03, 0x00, 0x6B, 0x00, 0x03}), registers({1, 2, 3, 4})) ==
        device_failure);
  // Values in the wrong table do not count.
  CHECK(encode(checked({0x03, 0x00, 0x6B, 0x00, 0x03}),
               bits({true, true, true})) == device_failure);
}

TEST_CASE("a request the parser never produces is answered 04, not formatted") {
  // CVE-2022-0367's write-and-read request, dressed up as a checked one: 0x17 is not served.
  ModbusRequest forged;
  forged.transaction_id = 0x1234;
  forged.unit_id = 0x11;
  forged.function = 0x17;
  CHECK(encode(forged, registers(std::vector<std::uint16_t>(125))) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0x97, 0x04});
  // A read of more registers than one reply holds.
  ModbusRequest oversized = checked({0x03, 0x00, 0x00, 0x00, 0x01});
  oversized.count = 200;
  CHECK(encode(oversized, registers(std::vector<std::uint16_t>(200))) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0x83, 0x04});
  // A single write without its value.
  ModbusRequest valueless = checked({0x06, 0x00, 0x01, 0x00, 0x03});
  valueless.registers.clear();
  CHECK(encode(valueless, {}) == Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x11, 0x86, 0x04});
}

TEST_CASE("a reused reply buffer holds only the latest reply") {
  std::vector<std::uint8_t> reply;
  format_reply(checked({0x04, 0x00, 0x00, 0x00, 0x7D}),
               registers(std::vector<std::uint16_t>(125, 0xFFFF)), reply);
  REQUIRE(reply.size() == 9 + 250);
  for (std::uint16_t i = 0; i < 50; ++i) {
    CAPTURE(i);
    format_reply(checked({0x03, 0x00, 0x00, 0x00, 0x01}), registers({i}), reply);
    CHECK(reply == Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x05, 0x11, 0x03, 0x02,
                         std::uint8_t(i >> 8), std::uint8_t(i)});
  }
}
