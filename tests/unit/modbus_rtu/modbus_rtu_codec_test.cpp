// Modbus RTU requests and reply checks, with frames from the Application Protocol's examples
// (their CRCs computed by the reference algorithm), and the frame length rule.
#include <doctest/doctest.h>

#include <array>

#include "modbus_rtu/codec.h"
#include "modbus_rtu/frame_length.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;
using test::framed;
using test::hex;

namespace {

Request request(Expected<Request, CodecError> built) {
  REQUIRE(built.has_value());
  return std::move(*built);
}

CodecError error_of(const Expected<Reply, CodecError>& reply) {
  REQUIRE_FALSE(reply.has_value());
  return reply.error();
}

}  // namespace

TEST_CASE("RTU read requests are slave, function, address, count and CRC") {
  CHECK(request(read_request(1, RegisterBank::holding, 0, 10)).frame ==
        hex("01 03 00 00 00 0A C5 CD"));
  CHECK(request(read_request(17, RegisterBank::holding, 107, 3)).frame ==
        hex("11 03 00 6B 00 03 76 87"));
  const Request input = request(read_request(17, RegisterBank::input, 8, 1));
  CHECK(input.frame == framed("11 04 00 08 00 01"));
  CHECK(input.slave == 17);
  CHECK(input.function == kReadInputRegisters);
}

TEST_CASE("RTU write requests: FC 6 one register, FC 16 a byte count and the registers") {
  CHECK(request(write_single_request(17, 1, 3)).frame == hex("11 06 00 01 00 03 9A 9B"));
  const std::array<std::uint16_t, 2> values{0x000A, 0x0102};
  CHECK(request(write_multiple_request(17, 1, values)).frame ==
        framed("11 10 00 01 00 02 04 00 0A 01 02"));
  CHECK(request(write_single_request(kBroadcastAddress, 1, 3)).slave == 0);
}

TEST_CASE("RTU requests refuse bad slaves, counts and ranges") {
  CHECK(read_request(0, RegisterBank::holding, 0, 1).error() == CodecError::bad_slave);
  CHECK(read_request(248, RegisterBank::holding, 0, 1).error() == CodecError::bad_slave);
  CHECK(read_request(1, RegisterBank::input, 0, 0).error() == CodecError::bad_count);
  CHECK(read_request(1, RegisterBank::input, 0, 126).error() == CodecError::bad_count);
  CHECK(read_request(1, RegisterBank::input, 0, 125).has_value());
  CHECK(read_request(1, RegisterBank::input, 65535, 2).error() == CodecError::bad_range);
  CHECK(read_request(1, RegisterBank::input, 65535, 1).has_value());
  CHECK(write_single_request(248, 0, 0).error() == CodecError::bad_slave);
  const std::vector<std::uint16_t> too_many(124, 0);
  CHECK(write_multiple_request(1, 0, too_many).error() == CodecError::bad_count);
  CHECK(write_multiple_request(1, 0, {}).error() == CodecError::bad_count);
  CHECK(write_multiple_request(1, 65535, std::vector<std::uint16_t>(2, 0)).error() ==
        CodecError::bad_range);
  CHECK(raw_request(1, {}).error() == CodecError::bad_pdu);
  CHECK(raw_request(1, std::vector<std::uint8_t>(254, 1)).error() == CodecError::bad_pdu);
}

TEST_CASE("an RTU pass-through request carries the PDU unchanged") {
  const auto pdu = hex("2B 0E 01 00");  // read device identification
  const Request raw = request(raw_request(30, pdu));
  CHECK(raw.frame == framed("1E 2B 0E 01 00"));
  CHECK(raw.function == 0x2B);
}

TEST_CASE("an RTU read reply gives its registers") {
  const Request read = request(read_request(17, RegisterBank::holding, 107, 3));
  const auto reply = parse_reply(read, hex("11 03 06 AE 41 56 52 43 40 49 AD"));
  REQUIRE(reply.has_value());
  CHECK(reply->registers == std::vector<std::uint16_t>{0xAE41, 0x5652, 0x4340});
  CHECK_FALSE(reply->exception.has_value());
  CHECK(reply->pdu == hex("03 06 AE 41 56 52 43 40"));
}

TEST_CASE("an RTU exception reply is a reply with the exception code") {
  const Request read = request(read_request(17, RegisterBank::holding, 107, 3));
  const auto reply = parse_reply(read, hex("11 83 02 C1 34"));
  REQUIRE(reply.has_value());
  CHECK(reply->exception == std::optional<std::uint8_t>(0x02));
  CHECK(reply->function == kReadHoldingRegisters);
  CHECK(reply->pdu == hex("83 02"));
  CHECK(exception_frame(17, kReadHoldingRegisters, ExceptionCode::illegal_data_address) ==
        hex("11 83 02 C1 34"));
}

TEST_CASE("RTU write replies must echo the request") {
  const Request single = request(write_single_request(17, 1, 3));
  CHECK(parse_reply(single, hex("11 06 00 01 00 03 9A 9B")).has_value());
  CHECK(error_of(parse_reply(single, framed("11 06 00 01 00 04"))) == CodecError::echo_mismatch);
  const std::array<std::uint16_t, 2> values{10, 258};
  const Request multiple = request(write_multiple_request(17, 1, values));
  CHECK(parse_reply(multiple, framed("11 10 00 01 00 02")).has_value());
  CHECK(error_of(parse_reply(multiple, framed("11 10 00 01 00 03"))) ==
        CodecError::echo_mismatch);
  CHECK(error_of(parse_reply(multiple, framed("11 10 00 01 00 02 00"))) ==
        CodecError::bad_length);
}

TEST_CASE("RTU replies are checked: CRC, slave, function, byte count, length") {
  const Request read = request(read_request(17, RegisterBank::holding, 107, 3));
  CHECK(error_of(parse_reply(read, hex("11 03 06 AE 41 56 52 43 40 49 AE"))) ==
        CodecError::crc_mismatch);
  CHECK(error_of(parse_reply(read, framed("12 03 06 AE 41 56 52 43 40"))) ==
        CodecError::wrong_slave);
  CHECK(error_of(parse_reply(read, framed("11 04 06 AE 41 56 52 43 40"))) ==
        CodecError::wrong_function);
  CHECK(error_of(parse_reply(read, framed("11 03 04 AE 41 56 52"))) == CodecError::bad_byte_count);
  CHECK(error_of(parse_reply(read, framed("11 03 06 AE 41 56 52 43 40 00"))) ==
        CodecError::bad_length);
  CHECK(error_of(parse_reply(read, framed("11 83 02 00"))) == CodecError::bad_length);
  CHECK(error_of(parse_reply(read, hex("11 83 02 C1"))) == CodecError::too_short);
}

TEST_CASE("an RTU pass-through reply of any function is relayed as its PDU") {
  const Request raw = request(raw_request(30, hex("2B 0E 01 00")));
  const auto reply = parse_reply(raw, framed("1E 2B 0E 01 01 00 00 01 00 03 41 42 43"));
  REQUIRE(reply.has_value());
  CHECK(reply->pdu == hex("2B 0E 01 01 00 00 01 00 03 41 42 43"));
}

TEST_CASE("RTU frame length follows libmodbus' rule") {
  const auto reply_length = [](std::string_view head) {
    return frame_length(FrameKind::reply, hex(head));
  };
  const auto request_length = [](std::string_view head) {
    return frame_length(FrameKind::request, hex(head));
  };
  CHECK(reply_length("11") == std::nullopt);
  CHECK(reply_length("11 83") == std::optional<std::size_t>(5));  // any exception
  CHECK(reply_length("11 03") == std::nullopt);                   // the byte count is next
  CHECK(reply_length("11 03 06") == std::optional<std::size_t>(11));
  CHECK(reply_length("11 04 FA") == std::optional<std::size_t>(255));
  CHECK(reply_length("11 06") == std::optional<std::size_t>(8));
  CHECK(reply_length("11 10") == std::optional<std::size_t>(8));
  CHECK(reply_length("11 2B") == std::optional<std::size_t>(kLengthByCrc));
  CHECK(request_length("11 03") == std::optional<std::size_t>(8));
  CHECK(request_length("11 06") == std::optional<std::size_t>(8));
  CHECK(request_length("11 10 00 01 00 02") == std::nullopt);
  CHECK(request_length("11 10 00 01 00 02 04") == std::optional<std::size_t>(13));
  CHECK(request_length("11 2B") == std::optional<std::size_t>(kLengthByCrc));
}
