// Modbus TCP devices (protocol "modbus-tcp"): the MBAP codec (modbus_rtu/mbap_codec.h), the
// reply framer that takes only its own transaction's reply (modbus_rtu/mbap_reply_framer.h),
// the framing the driver, scan, raw and pass-through choose by protocol
// (modbus_rtu/adu_framing.h), and the driver polling a device over MBAP.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>

#include "driver/family.h"
#include "modbus_rtu/adu_framing.h"
#include "modbus_rtu/crc.h"
#include "modbus_rtu/forwarding.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/mbap_codec.h"
#include "modbus_rtu/mbap_reply_framer.h"
#include "modbus_rtu/profile_reader.h"
#include "modbus_rtu/rtu_driver.h"
#include "modbus_rtu/scan_probe.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"
#include "unit/support/fake_bus.h"
#include "unit/support/rtu_test_profile.h"

using namespace tiltgate;
using namespace tiltgate::modbus_rtu;
using modbus_rtu::test::hex;

namespace {

Bytes concat(Bytes a, const Bytes& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// A read of 3 holding registers at 107 for unit 17, as transaction 0x1234.
MbapReplyFramer read_framer(std::uint8_t unit = 17, std::uint16_t transaction = 0x1234) {
  auto request = AduFraming(Adu::mbap).request_for(unit, [](std::uint8_t slave) {
    return read_request(slave, RegisterBank::holding, 107, 3);
  });
  REQUIRE(request.has_value());
  MbapReplyFramer framer(*request, transaction);
  framer.reset();
  return framer;
}

std::uint16_t get_transaction(const Bytes& frame) {
  return static_cast<std::uint16_t>(frame[0] << 8 | frame[1]);
}

const Bytes kReply = hex("12 34 00 00 00 09 11 03 06 02 2B 00 00 00 64");

}  // namespace

TEST_CASE("MBAP: a request is the header (transaction, protocol 0, length, unit) and the PDU") {
  // The Implementation Guide's example: read 3 holding registers from 107.
  CHECK(read_framer().request_bytes() == hex("12 34 00 00 00 06 11 03 00 6B 00 03"));
  CHECK(mbap_bytes(MbapFrame{7, 255, hex("11")}) == hex("00 07 00 00 00 02 FF 11"));
}

TEST_CASE("MBAP: the stream cuts frames by their length, whole, split or joined") {
  const Bytes two = concat(hex("00 01 00 00 00 03 05 83 02"), kReply);
  MbapStream joined;
  CHECK(joined.feed(two) == 2);
  CHECK(joined.next() == MbapFrame{1, 5, hex("83 02")});
  CHECK(joined.next() == MbapFrame{0x1234, 17, hex("03 06 02 2B 00 00 00 64")});
  CHECK_FALSE(joined.next().has_value());

  // One byte at a time, as a slow stream may deliver it: nothing before the last byte.
  MbapStream split;
  for (std::size_t i = 0; i + 1 < kReply.size(); ++i) CHECK(split.feed({&kReply[i], 1}) == 0);
  CHECK(split.feed({&kReply.back(), 1}) == 1);
  CHECK(split.buffered() == 0);
}

TEST_CASE("MBAP: bytes that start no frame (protocol id not 0, impossible length) are dropped") {
  MbapStream stream;
  // Protocol id 1, then a length of 0 before the real frame.
  const Bytes junk = hex("00 01 00 01 00 03 05 83 02");
  CHECK(stream.feed(concat(junk, kReply)) >= 1);
  std::optional<MbapFrame> last;
  while (auto frame = stream.next()) last = frame;
  REQUIRE(last.has_value());
  CHECK(last->transaction == 0x1234);
  CHECK(stream.bytes_discarded() > 0);
}

TEST_CASE("MBAP framer: another transaction's reply is dropped, the request's own taken") {
  MbapReplyFramer framer = read_framer();
  // A late reply to the request before (transaction 0x1233) with other values, then this one's.
  const Bytes late = hex("12 33 00 00 00 09 11 03 06 00 01 00 01 00 01");
  CHECK_FALSE(framer.feed(late));
  CHECK(framer.frames_dropped() == 1);
  // Another unit's reply with this transaction id is not this request's either.
  CHECK_FALSE(framer.feed(hex("12 34 00 00 00 09 12 03 06 00 01 00 01 00 01")));
  CHECK(framer.frames_dropped() == 2);
  CHECK(framer.report().rejected_verdict.empty());  // skipped, not garbled
  // This one's reply split over two reads.
  CHECK_FALSE(framer.feed({kReply.data(), 5}));
  CHECK(framer.feed({kReply.data() + 5, kReply.size() - 5}));
  REQUIRE(framer.reply().has_value());
  REQUIRE(framer.reply()->has_value());
  CHECK((*framer.reply())->registers == std::vector<std::uint16_t>{0x022B, 0, 0x64});
}

TEST_CASE("MBAP framer: the late reply and the reply in one read still give this reply") {
  MbapReplyFramer framer = read_framer();
  CHECK(framer.feed(concat(hex("12 33 00 00 00 09 11 03 06 00 01 00 01 00 01"), kReply)));
  CHECK((*framer.reply())->registers == std::vector<std::uint16_t>{0x022B, 0, 0x64});
}

TEST_CASE("MBAP framer: an exception reply is the device's refusal, a bad length an error") {
  MbapReplyFramer refused = read_framer();
  CHECK(refused.feed(hex("12 34 00 00 00 03 11 83 02")));
  REQUIRE(refused.reply()->has_value());
  CHECK((*refused.reply())->exception == 0x02);

  // The header's length fits, but the byte count says 3 registers and 2 came: a protocol error
  // that ends the wait, as on a serial line.
  MbapReplyFramer short_reply = read_framer();
  CHECK(short_reply.feed(hex("12 34 00 00 00 07 11 03 06 02 2B 00 00")));
  REQUIRE_FALSE(short_reply.reply()->has_value());
  CHECK(short_reply.reply()->error() == CodecError::bad_length);
}

TEST_CASE("MBAP framing: every unit id 0..255 is a device's, and each request a new transaction") {
  AduFraming framing(Adu::mbap, 41);
  auto build = [](std::uint8_t slave) { return read_request(slave, RegisterBank::input, 0, 2); };
  auto first = framing.exchange(255, build);
  auto second = framing.exchange(0, build);
  REQUIRE(first.has_value());
  REQUIRE(second.has_value());
  CHECK((*first)->request_bytes() == hex("00 29 00 00 00 06 FF 04 00 00 00 02"));
  CHECK((*second)->request_bytes() == hex("00 2A 00 00 00 06 00 04 00 00 00 02"));
  // The serial line's RTU framing of the same request is unchanged.
  auto rtu = AduFraming(Adu::rtu).exchange(17, build);
  REQUIRE(rtu.has_value());
  CHECK((*rtu)->request_bytes() == modbus_rtu::test::framed("11 04 00 00 00 02"));
  CHECK_FALSE(AduFraming(Adu::rtu).exchange(255, build).has_value());
  CHECK(adu_of("modbus-tcp") == Adu::mbap);
  CHECK(adu_of("modbus-rtu") == Adu::rtu);
}

TEST_CASE("MBAP pass-through: the PDU in a frame of its own, the reply PDU relayed unchanged") {
  auto made = forward_mbap_request(255, hex("08 00 00 A5 37"));
  REQUIRE(made.has_value());
  auto& forwarded = **made;
  const Bytes& sent = forwarded.request_bytes();
  REQUIRE(sent.size() == 12);
  CHECK(Bytes(sent.begin() + 2, sent.end()) == hex("00 00 00 06 FF 08 00 00 A5 37"));
  forwarded.framer().reset();
  // Its reply carries the request's transaction id; another's is dropped.
  Bytes other = concat(Bytes{std::uint8_t(sent[0] ^ 1), sent[1]}, hex("00 00 00 03 FF 88 01"));
  CHECK_FALSE(forwarded.framer().feed(other));
  Bytes reply = concat(Bytes{sent[0], sent[1]}, hex("00 00 00 03 FF 88 01"));
  CHECK(forwarded.framer().feed(reply));
  REQUIRE(forwarded.reply_pdu().has_value());
  CHECK(*forwarded.reply_pdu() == hex("88 01"));
  CHECK_FALSE(forward_mbap_request(1, {}).has_value());
}

TEST_CASE("MBAP scan: a gateway's 0x0B (or 0x0A) for a unit id is nobody there, 0x01 a device") {
  auto outcome_of = [](std::string_view reply_pdu) {
    auto request = AduFraming(Adu::mbap).request_for(
        9, [](std::uint8_t slave) { return probe_request(slave, std::nullopt); });
    MbapReplyFramer framer(*request, 5);
    framer.reset();
    const Bytes pdu = hex(reply_pdu);
    Bytes frame = mbap_bytes(MbapFrame{5, 9, pdu});
    REQUIRE(framer.feed(frame));
    return probe_outcome(framer, 9, Adu::mbap);
  };
  CHECK(outcome_of("91 0B").outcome == ProbeOutcome::silent);
  CHECK(outcome_of("91 0A").outcome == ProbeOutcome::silent);
  CHECK(outcome_of("91 01").outcome == ProbeOutcome::answered);
  CHECK(outcome_of("11 02 09 FF").outcome == ProbeOutcome::answered);
}

TEST_CASE("Modbus TCP driver: polls a device over MBAP and never takes a late reply") {
  boost::asio::io_context io;
  tiltgate::test::FakeLine line(io.get_executor());
  SimulatedDevice device = rtu_inclinometer(3);
  set_inclinometer_angles(device, 1.5, -2.5);
  std::vector<Bytes> sent;
  // The device behind the fake connection: the MBAP request's PDU answered as the simulated
  // device answers it, in a frame with the request's ids, after a stale frame with the previous
  // transaction's id and other registers (a reply that came too late for the request before).
  line.reply = [&](const LineRequest& request) {
    sent.push_back(request.bytes);
    MbapStream stream;
    stream.feed(request.bytes);
    const MbapFrame asked = *stream.next();
    Bytes rtu{asked.unit};
    rtu.insert(rtu.end(), asked.pdu.begin(), asked.pdu.end());
    append_crc(rtu);
    const Bytes answer = device.respond(rtu)->frame;
    const Bytes pdu(answer.begin() + 1, answer.end() - 2);
    Bytes stale = pdu;
    for (std::size_t i = 2; i < stale.size(); ++i) stale[i] = 0x7F;
    return concat(mbap_bytes(MbapFrame{std::uint16_t(asked.transaction - 1), asked.unit, stale}),
                  mbap_bytes(MbapFrame{asked.transaction, asked.unit, pdu}));
  };
  auto profile = parse_device_profile(tiltgate::test::kRtuTestProfile, "test.toml");
  REQUIRE(profile.has_value());
  RtuDriverOptions options;
  options.name = "tcp-device";
  options.slave = 3;
  options.profile = std::move(*profile);
  options.adu = Adu::mbap;
  options.model = "modbus-tcp";
  RtuDriver driver(std::move(options));
  CHECK(driver.model() == "modbus-tcp");
  boost::asio::co_spawn(io, driver.poll(line), boost::asio::detached);
  io.run();
  REQUIRE(sent.size() >= 2);
  CHECK(sent[0][6] == 3);                     // the unit id
  CHECK(get_transaction(sent[0]) + 1 == get_transaction(sent[1]));
  REQUIRE(driver.state().reading.has_value());
  CHECK(driver.state().reading->angle_x == doctest::Approx(1.5));
  CHECK(driver.state().reading->angle_y == doctest::Approx(-2.5));
}
