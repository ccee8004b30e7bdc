// The Modbus TCP request parser: every supported function, every malformed case. Frames follow
// the examples of the Modbus Application Protocol V1.1b3, section 6.
#include <doctest/doctest.h>

#include <cstdint>
#include <variant>
#include <vector>

#include "modbus_tcp/modbus_request.h"

using namespace tiltgate;

namespace {

using Bytes = std::vector<std::uint8_t>;

// An ADU with a correct MBAP header (transaction 0x1234, protocol 0, unit 0x11) around `pdu`.
Bytes frame(const Bytes& pdu, std::uint8_t unit = 0x11) {
  const auto length = std::uint16_t(pdu.size() + 1);
  Bytes adu{0x12, 0x34, 0x00, 0x00, std::uint8_t(length >> 8), std::uint8_t(length & 0xFF), unit};
  adu.insert(adu.end(), pdu.begin(), pdu.end());
  return adu;
}

ModbusRequest accepted(const Bytes& adu) {
  ParsedAdu parsed = parse_adu(adu);
  REQUIRE(std::holds_alternative<ModbusRequest>(parsed));
  return std::get<ModbusRequest>(parsed);
}

// The exception the parser answers itself; the frame never becomes a ModbusRequest, so it can
// reach neither the handler nor libmodbus.
ModbusException rejected(const Bytes& adu) {
  ParsedAdu parsed = parse_adu(adu);
  REQUIRE(std::holds_alternative<RejectedRequest>(parsed));
  const auto& rejection = std::get<RejectedRequest>(parsed);
  CHECK(rejection.reply == exception_reply(adu, rejection.exception));
  return rejection.exception;
}

FramingError framing_error(const Bytes& adu) {
  ParsedAdu parsed = parse_adu(adu);
  REQUIRE(std::holds_alternative<FramingError>(parsed));
  return std::get<FramingError>(parsed);
}

Bytes operator+(Bytes a, const Bytes& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

Bytes read_pdu(std::uint8_t function, std::uint16_t address, std::uint16_t count) {
  return {function, std::uint8_t(address >> 8), std::uint8_t(address), std::uint8_t(count >> 8),
          std::uint8_t(count)};
}

// 15 / 16 with `data_bytes` zero data bytes after the byte count.
Bytes write_multiple_pdu(std::uint8_t function, std::uint16_t address, std::uint16_t count,
                         std::uint8_t byte_count, std::size_t data_bytes) {
  Bytes pdu = read_pdu(function, address, count);
  pdu.push_back(byte_count);
  pdu.resize(pdu.size() + data_bytes, 0);
  return pdu;
}

}  // namespace

TEST_CASE("reads 01-04 give their table, address and count") {
  struct Case {
    std::uint8_t function;
    ModbusTable table;
  };
  for (const Case c : {Case{0x01, ModbusTable::coil}, Case{0x02, ModbusTable::discrete},
                       Case{0x03, ModbusTable::holding}, Case{0x04, ModbusTable::input}}) {
    CAPTURE(int(c.function));
    const Bytes adu = frame(read_pdu(c.function, 0x006B, 3));
    const ModbusRequest request = accepted(adu);
    CHECK(request.transaction_id == 0x1234);
    CHECK(request.unit_id == 0x11);
    CHECK(request.function == c.function);
    CHECK(request.table == c.table);
    CHECK_FALSE(request.is_write);
    CHECK(request.address == 0x006B);
    CHECK(request.count == 3);
    CHECK(request.adu == adu);
  }
}

TEST_CASE("05 write single coil: FF00 is on, 0000 is off, anything else is 03") {
  const ModbusRequest on = accepted(frame({0x05, 0x00, 0xAC, 0xFF, 0x00}));
  CHECK(on.table == ModbusTable::coil);
  CHECK(on.is_write);
  CHECK(on.address == 0x00AC);
  CHECK(on.count == 1);
  CHECK(on.bits == std::vector<bool>{true});
  CHECK(accepted(frame({0x05, 0x00, 0xAC, 0x00, 0x00})).bits == std::vector<bool>{false});
  CHECK(rejected(frame({0x05, 0x00, 0xAC, 0x00, 0x01})) == ModbusException::illegal_value);
  CHECK(rejected(frame({0x05, 0x00, 0xAC, 0xFF, 0xFF})) == ModbusException::illegal_value);
}

TEST_CASE("06 write single register carries its value") {
  const ModbusRequest request = accepted(frame({0x06, 0x00, 0x01, 0x00, 0x03}));
  CHECK(request.table == ModbusTable::holding);
  CHECK(request.is_write);
  CHECK(request.address == 1);
  CHECK(request.count == 1);
  CHECK(request.registers == std::vector<std::uint16_t>{3});
}

TEST_CASE("15 write multiple coils unpacks the bits least significant first") {
  // Section 6.11: coils 20-29 (address 0x13) set to CD 01.
  const ModbusRequest request =
      accepted(frame({0x0F, 0x00, 0x13, 0x00, 0x0A, 0x02, 0xCD, 0x01}));
  CHECK(request.table == ModbusTable::coil);
  CHECK(request.is_write);
  CHECK(request.address == 0x13);
  CHECK(request.count == 10);
  CHECK(request.bits ==
        std::vector<bool>{true, false, true, true, false, false, true, true, true, false});
}

TEST_CASE("16 write multiple registers carries the values in order") {
  // Section 6.12: registers 2-3 (address 1) set to 000A 0102.
  const ModbusRequest request =
      accepted(frame({0x10, 0x00, 0x01, 0x00, 0x02, 0x04, 0x00, 0x0A, 0x01, 0x02}));
  CHECK(request.table == ModbusTable::holding);
  CHECK(request.address == 1);
  CHECK(request.count == 2);
  CHECK(request.registers == std::vector<std::uint16_t>{0x000A, 0x0102});
}

TEST_CASE("unsupported functions are answered 01 by the parser, however short or long") {
  CHECK(rejected(frame({0x07})) == ModbusException::illegal_function);  // short 07
  CHECK(rejected(frame({0x0C})) == ModbusException::illegal_function);  // short 12
  CHECK(rejected(frame({0x14, 0x00, 0x00, 0xA5, 0x37})) == ModbusException::illegal_function);
  CHECK(rejected(frame({0x11})) == ModbusException::illegal_function);
  CHECK(rejected(frame({0x2B, 0x0D, 0x00, 0x00})) == ModbusException::illegal_function);  // 43/13
  CHECK(rejected(frame({0x00})) == ModbusException::illegal_function);
  CHECK(rejected(frame({0x83, 0x02})) == ModbusException::illegal_function);
  // 0x17 write-and-read claiming 121 registers (242 bytes) it does not carry: CVE-2022-0367.
  CHECK(rejected(frame({0x17, 0x00, 0x00, 0x00, 0x7D, 0x00, 0x00, 0x00, 0x79, 0xF2, 0x00}))
        == ModbusException::illegal_function);
  // ... and one with a byte count larger than the whole frame.
  CHECK(rejected(frame({0x17, 0x00, 0x00, 0x00, 0x01, 0xFF, 0xF0, 0x00, 0x01, 0xFF}))
        == ModbusException::illegal_function);
}

TEST_CASE("43 / 14 read device identification carries its read code and object id") {
  // Section 6.21's example: basic stream from object 0.
  const Bytes adu = frame({0x2B, 0x0E, 0x01, 0x00});
  const ModbusRequest basic = accepted(adu);
  CHECK(basic.function == 0x2B);
  CHECK_FALSE(basic.is_write);
  CHECK(basic.read_device_id_code == 0x01);
  CHECK(basic.object_id == 0x00);
  CHECK(basic.adu == adu);
  const ModbusRequest one = accepted(frame({0x2B, 0x0E, 0x04, 0x81}));
  CHECK(one.read_device_id_code == 0x04);
  CHECK(one.object_id == 0x81);
  // Any object id is the unit's business (02 or a restart), not the parser's.
  CHECK(accepted(frame({0x2B, 0x0E, 0x03, 0xFF})).object_id == 0xFF);
  CHECK(accepted(frame({0x2B, 0x0E, 0x02, 0x42})).object_id == 0x42);
}

TEST_CASE("43 / 14 with a byte missing or extra or a read code outside 1..4 is 03") {
  CHECK(rejected(frame({0x2B})) == ModbusException::illegal_value);
  CHECK(rejected(frame({0x2B, 0x0E})) == ModbusException::illegal_value);
  CHECK(rejected(frame({0x2B, 0x0E, 0x01})) == ModbusException::illegal_value);
  CHECK(rejected(frame({0x2B, 0x0E, 0x01, 0x00, 0x00})) == ModbusException::illegal_value);
  CHECK(rejected(frame(Bytes{0x2B, 0x0E, 0x01, 0x00} + Bytes(249, 0x00))) ==
        ModbusException::illegal_value);
  CHECK(rejected(frame({0x2B, 0x0E, 0x00, 0x00})) == ModbusException::illegal_value);
  CHECK(rejected(frame({0x2B, 0x0E, 0x05, 0x00})) == ModbusException::illegal_value);
  CHECK(rejected(frame({0x2B, 0x0E, 0xFF, 0x00})) == ModbusException::illegal_value);
}

TEST_CASE("43 with another MEI type is 01, whatever follows") {
  CHECK(rejected(frame({0x2B, 0x0D})) == ModbusException::illegal_function);
  CHECK(rejected(frame({0x2B, 0x0D, 0x00, 0x00, 0x01, 0x00, 0x00})) ==
        ModbusException::illegal_function);
  CHECK(rejected(frame({0x2B, 0x00, 0x01, 0x00})) == ModbusException::illegal_function);
  CHECK(rejected(frame({0x2B, 0xFF, 0x01, 0x00})) == ModbusException::illegal_function);
}

TEST_CASE("the exception reply keeps transaction and unit and sets the function's high bit") {
  const Bytes reply = exception_reply(frame({0x07}, 0x2A), ModbusException::illegal_function);
  CHECK(reply == Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x2A, 0x87, 0x01});
}

TEST_CASE("quantities of 0 or beyond the spec's limits are 03, the limits themselves pass") {
  struct Limit {
    std::uint8_t function;
    std::uint16_t max;
  };
  for (const Limit l : {Limit{0x01, 2000}, Limit{0x02, 2000}, Limit{0x03, 125}, Limit{0x04, 125}}) {
    CAPTURE(int(l.function));
    CHECK(rejected(frame(read_pdu(l.function, 0, 0))) == ModbusException::illegal_value);
    CHECK(rejected(frame(read_pdu(l.function, 0, l.max + 1))) == ModbusException::illegal_value);
    CHECK(rejected(frame(read_pdu(l.function, 0, 0xFFFF))) == ModbusException::illegal_value);
    CHECK(accepted(frame(read_pdu(l.function, 0, l.max))).count == l.max);
  }
  CHECK(rejected(frame(write_multiple_pdu(0x0F, 0, 0, 0, 0))) == ModbusException::illegal_value);
  CHECK(rejected(frame(write_multiple_pdu(0x0F, 0, 1969, 247, 247))) ==
        ModbusException::illegal_value);
  CHECK(accepted(frame(write_multiple_pdu(0x0F, 0, 1968, 246, 246))).bits.size() == 1968);
  CHECK(rejected(frame(write_multiple_pdu(0x10, 0, 0, 0, 0))) == ModbusException::illegal_value);
  CHECK(rejected(frame(write_multiple_pdu(0x10, 0, 124, 248, 246))) ==
        ModbusException::illegal_value);
  CHECK(accepted(frame(write_multiple_pdu(0x10, 0, 123, 246, 246))).registers.size() == 123);
}

TEST_CASE("a byte count that disagrees with the quantity or the frame is 03") {
  // 10 coils need 2 bytes.
  CHECK(rejected(frame(write_multiple_pdu(0x0F, 0, 10, 1, 1))) == ModbusException::illegal_value);
  CHECK(rejected(frame(write_multiple_pdu(0x0F, 0, 10, 3, 3))) == ModbusException::illegal_value);
  // Right byte count, data missing or extra.
  CHECK(rejected(frame(write_multiple_pdu(0x0F, 0, 10, 2, 1))) == ModbusException::illegal_value);
  CHECK(rejected(frame(write_multiple_pdu(0x0F, 0, 10, 2, 3))) == ModbusException::illegal_value);
  // 2 registers need 4 bytes.
  CHECK(rejected(frame(write_multiple_pdu(0x10, 0, 2, 3, 3))) == ModbusException::illegal_value);
  CHECK(rejected(frame(write_multiple_pdu(0x10, 0, 2, 4, 2))) == ModbusException::illegal_value);
  CHECK(rejected(frame(write_multiple_pdu(0x10, 0, 2, 4, 5))) == ModbusException::illegal_value);
  // A byte count claiming more than the frame can hold.
  CHECK(rejected(frame(write_multiple_pdu(0x10, 0, 2, 0xFF, 4))) ==
        ModbusException::illegal_value);
}

TEST_CASE("a PDU shorter or longer than its function's layout is 03") {
  for (std::uint8_t function : {0x01, 0x02, 0x03, 0x04, 0x05, 0x06}) {
    CAPTURE(int(function));
    Bytes pdu = read_pdu(function, 0, 1);
    pdu[3] = function == 0x05 ? 0xFF : 0x00;  // a valid 05 value when the layout is right
    pdu[4] = function == 0x05 ? 0x00 : 0x01;
    CHECK(rejected(frame({function})) == ModbusException::illegal_value);
    CHECK(rejected(frame(Bytes(pdu.begin(), pdu.end() - 1))) == ModbusException::illegal_value);
    Bytes longer = pdu;
    longer.push_back(0);
    CHECK(rejected(frame(longer)) == ModbusException::illegal_value);
    accepted(frame(pdu));
  }
  for (std::uint8_t function : {0x0F, 0x10}) {
    CAPTURE(int(function));
    CHECK(rejected(frame({function})) == ModbusException::illegal_value);
    CHECK(rejected(frame({function, 0x00, 0x00, 0x00, 0x01})) == ModbusException::illegal_value);
  }
}

TEST_CASE("a range running past address 0xFFFF is 02, one ending at 0xFFFF passes") {
  CHECK(rejected(frame(read_pdu(0x03, 0xFFFF, 2))) == ModbusException::illegal_address);
  CHECK(rejected(frame(read_pdu(0x01, 0xFF00, 257))) == ModbusException::illegal_address);
  CHECK(accepted(frame(read_pdu(0x03, 0xFFFF, 1))).address == 0xFFFF);
  CHECK(accepted(frame(read_pdu(0x04, 0xFF83, 125))).count == 125);
  CHECK(rejected(frame(write_multiple_pdu(0x10, 0xFFFF, 2, 4, 4))) ==
        ModbusException::illegal_address);
  CHECK(rejected(frame(write_multiple_pdu(0x0F, 0xFFFA, 7, 1, 1))) ==
        ModbusException::illegal_address);
  CHECK(accepted(frame({0x06, 0xFF, 0xFF, 0x12, 0x34})).address == 0xFFFF);
}

TEST_CASE("an MBAP header with a protocol id or length out of range cannot be framed") {
  Bytes adu = frame(read_pdu(0x03, 0, 1));
  adu[3] = 0x01;  // protocol id 1
  CHECK(framing_error(adu) == FramingError::protocol_id);
  CHECK(framing_error({0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x01}) == FramingError::length);
  CHECK(framing_error({0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x01}) == FramingError::length);
  Bytes too_long = frame(Bytes(254, 0x03));  // length field 255
  CHECK(framing_error(too_long) == FramingError::length);
  // The largest PDU, 253 bytes, frames (and is then checked as a request).
  CHECK(rejected(frame(Bytes(253, 0x03))) == ModbusException::illegal_value);
  // A frame whose length field does not match the bytes given.
  Bytes truncated = frame(read_pdu(0x03, 0, 1));
  truncated.pop_back();
  CHECK(framing_error(truncated) == FramingError::length);
  CHECK(framing_error({0x00, 0x01, 0x00}) == FramingError::length);
}

TEST_CASE("the frame assembler takes frames whole, a byte at a time, or several at once") {
  const Bytes first = frame(read_pdu(0x03, 0, 1));
  const Bytes second = frame(write_multiple_pdu(0x10, 0, 2, 4, 4));
  Bytes stream = first;
  stream.insert(stream.end(), second.begin(), second.end());

  SUBCASE("a byte at a time") {
    ModbusFrameAssembler frames;
    std::vector<Bytes> got;
    for (std::uint8_t byte : stream) {
      REQUIRE(!frames.space().empty());
      frames.space()[0] = byte;
      frames.commit(1);
      auto next = frames.next();
      if (auto* adu = std::get_if<std::span<const std::uint8_t>>(&next)) {
        got.emplace_back(adu->begin(), adu->end());
        frames.pop();
      } else {
        CHECK(std::holds_alternative<ModbusFrameAssembler::NeedMore>(next));
      }
    }
    CHECK(got == std::vector<Bytes>{first, second});
    CHECK(frames.buffered() == 0);
  }
  SUBCASE("two pipelined frames in one read") {
    ModbusFrameAssembler frames;
    std::copy(stream.begin(), stream.end(), frames.space().begin());
    frames.commit(stream.size());
    auto next = frames.next();
    REQUIRE(std::holds_alternative<std::span<const std::uint8_t>>(next));
    CHECK(Bytes(std::get<1>(next).begin(), std::get<1>(next).end()) == first);
    frames.pop();
    next = frames.next();
    REQUIRE(std::holds_alternative<std::span<const std::uint8_t>>(next));
    CHECK(Bytes(std::get<1>(next).begin(), std::get<1>(next).end()) == second);
    frames.pop();
    CHECK(std::holds_alternative<ModbusFrameAssembler::NeedMore>(frames.next()));
  }
  SUBCASE("a bad header is reported as soon as its 7 bytes are in") {
    ModbusFrameAssembler frames;
    const Bytes http{'G', 'E', 'T', ' ', '/', ' ', 'H'};
    std::copy(http.begin(), http.end() - 1, frames.space().begin());
    frames.commit(http.size() - 1);
    CHECK(std::holds_alternative<ModbusFrameAssembler::NeedMore>(frames.next()));
    frames.space()[0] = http.back();
    frames.commit(1);
    const auto next = frames.next();
    REQUIRE(std::holds_alternative<FramingError>(next));
    CHECK(std::get<FramingError>(next) == FramingError::protocol_id);
  }
  SUBCASE("a maximal 260-byte frame fits the buffer") {
    ModbusFrameAssembler frames;
    const Bytes biggest = frame(Bytes(253, 0x03));
    REQUIRE(biggest.size() == max_adu_size);
    REQUIRE(frames.space().size() >= max_adu_size);
    std::copy(biggest.begin(), biggest.end(), frames.space().begin());
    frames.commit(biggest.size());
    CHECK(std::holds_alternative<std::span<const std::uint8_t>>(frames.next()));
  }
}
