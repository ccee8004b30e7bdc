// The Dyna bus simulator over a real pseudo-terminal, in both protocols: the test opens the
// slave side as a raw tty, as the gateway would, sends requests and reads what comes back.
// Single-threaded: the test pumps the io_context while it waits, always up to a deadline.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <cerrno>
#include <chrono>
#include <filesystem>

#include "serial/serial_line.h"
#include "sim/support/raw_tty_client.h"
#include "sim/support/run_coroutine.h"
#include "sim/support/termios2_skip.h"
#include "spectron/ascii_frame_parser.h"
#include "spectron/nine_bit_codec.h"
#include "spectron/reply_framers.h"
#include "spectron/simulator.h"
#include "unit/spectron/spectron_test_vectors.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace tiltgate::spectron;
using namespace std::chrono_literals;
using spectron::test::bytes;

namespace {

using Bytes = std::vector<std::uint8_t>;
using tiltgate::test::kReplyDeadline;
using tiltgate::test::kSilence;
using tiltgate::test::run_until;

// The gateway's side of the bus. Replies are split into 9-bit lines and Modbus-ASCII frames at
// the same time; each test reads the one it needs.
class BusClient {
 public:
  BusClient(boost::asio::io_context& io, const std::string& path) : tty_(io, path) {}

  void send(const Bytes& data) { tty_.send(data); }
  void send(std::string_view text) { send(bytes(text)); }
  void send(const NineBitRequest& request) { send(wire_bytes(request)); }
  void send(const NineBitRequestResult& request) {
    REQUIRE(request.has_value());
    send(*request);
  }
  void send(const AsciiRequestResult& request) {
    REQUIRE(request.has_value());
    send(encode(*request));
  }

  // The next 9-bit reply line, or nullopt once `limit` has passed.
  std::optional<std::string> line(std::chrono::milliseconds limit = kReplyDeadline) {
    return wait_for([&] { return lines_.next(); }, limit);
  }
  // The next Modbus-ASCII frame with a good LRC, or nullopt once `limit` has passed.
  std::optional<AsciiFrame> frame(std::chrono::milliseconds limit = kReplyDeadline) {
    return wait_for([&] { return frames_.next(); }, limit);
  }

  template <class Request>
  std::string ask(const Request& request) {
    send(request);
    auto reply = line();
    REQUIRE_MESSAGE(reply.has_value(), "no reply within the deadline");
    return *reply;
  }
  AsciiFrame exchange(const AsciiRequestResult& request) {
    send(request);
    auto reply = frame();
    REQUIRE_MESSAGE(reply.has_value(), "no reply within the deadline");
    return *reply;
  }

  const Bytes& raw() const { return tty_.raw(); }
  const AsciiFrameParser& frames() const { return frames_; }
  const NineBitLineParser& lines() const { return lines_; }
  ssize_t read_once(int& error) { return tty_.read_once(error); }

 private:
  template <class Take>
  auto wait_for(Take take, std::chrono::milliseconds limit) -> decltype(take()) {
    return tty_.wait_for(
        take,
        [&](std::span<const std::uint8_t> chunk) {
          lines_.feed(chunk);
          frames_.feed(chunk);
        },
        limit);
  }

  tiltgate::test::RawTtyClient tty_;
  NineBitLineParser lines_;
  AsciiFrameParser frames_;
};

struct Bus {
  boost::asio::io_context io;
  tiltgate::test::ScratchDir dir{"tiltgate-spectron-sim"};
  std::optional<DynaSimulator> sim;  // last: gone before the directory and the io_context

  Bus(Protocol protocol, std::vector<SimulatedDynaOptions> sensors,
      std::optional<std::uint32_t> pace_baud = std::nullopt) {
    DynaSimulatorOptions options;
    options.protocol = protocol;
    options.sensors = std::move(sensors);
    options.link_path = dir.path("ttyDYNA");
    options.pace_baud = pace_baud;
    sim.emplace(io, std::move(options));
    const auto started = sim->start();
    REQUIRE_MESSAGE(started.has_value(), started.error());
  }
};

SimulatedDynaOptions dyna(std::uint8_t address, std::int16_t counts = 1001) {
  SimulatedDynaOptions options;
  options.address = address;
  options.counts = counts;
  options.temperature = -40;
  return options;
}

std::int32_t number(const std::string& line) {
  const auto parsed = parse_nine_bit_number(line);
  REQUIRE_MESSAGE(parsed.has_value(), describe(parsed.error()));
  return parsed->value;
}

}  // namespace

TEST_CASE("9-bit: the simulator answers every command over a pseudo-terminal") {
  Bus bus(Protocol::nine_bit, {dyna(0)});
  BusClient client(bus.io, bus.sim->link_path());
  CHECK(number(client.ask(nine_bit_read_sensor_request(0))) == 1001);
  CHECK(number(client.ask(nine_bit_read_temperature_request(0))) == -40);
  CHECK(*parse_nine_bit_firmware(client.ask(nine_bit_firmware_request(0))) == "DYNA 1.07");
  CHECK(number(client.ask(nine_bit_read_eeprom_request(0, 4))) == 12345);
  CHECK(client.ask(nine_bit_write_eeprom_request(0, 6, 1)) == "");
  CHECK(number(client.ask(nine_bit_read_eeprom_request(0, 6))) == 1);
  CHECK(number(client.ask(nine_bit_read_sensor_request(0))) == 1000);
  CHECK(client.ask(nine_bit_write_eeprom_request(0, 22, 7, '\t')) == "");
  CHECK(client.ask(nine_bit_reset_request(0)) == "");
  CHECK(bus.sim->sensor(0).baud_code() == 7);
  CHECK(bus.sim->sensor(0).resets() == 1);
  CHECK(bus.sim->counters().requests_seen == 9);
  CHECK(run_until(bus.io, [&] { return bus.sim->counters().replies_sent == 9; }));
}

TEST_CASE("9-bit: a module moved by a write to location 16 answers only at its new address") {
  Bus bus(Protocol::nine_bit, {dyna(0)});
  BusClient client(bus.io, bus.sim->link_path());
  CHECK(client.ask(nine_bit_write_eeprom_request(0, 16, 42)) == "");
  CHECK(bus.sim->sensor_by_address(42) == &bus.sim->sensor(0));
  CHECK(bus.sim->sensor_by_address(0) == nullptr);
  client.send(nine_bit_read_sensor_request(0));
  CHECK_FALSE(client.line(kSilence).has_value());
  CHECK(number(client.ask(nine_bit_read_eeprom_request(42, 16))) == 42);
}

TEST_CASE("9-bit: only the addressed module answers, other addresses get silence") {
  Bus bus(Protocol::nine_bit, {dyna(1, 111), dyna(2, 222)});
  BusClient client(bus.io, bus.sim->link_path());
  CHECK(number(client.ask(nine_bit_read_sensor_request(2))) == 222);
  CHECK(number(client.ask(nine_bit_read_sensor_request(1))) == 111);
  client.send(nine_bit_read_sensor_request(3));
  CHECK_FALSE(client.line(kSilence).has_value());
  CHECK(bus.sim->counters().requests_seen == 3);
  CHECK(bus.sim->counters().replies_sent == 2);
}

TEST_CASE("9-bit: noise before a request costs at most that noise, framing resumes") {
  Bus bus(Protocol::nine_bit, {dyna(5)});
  BusClient client(bus.io, bus.sim->link_path());
  // A noise line: its first byte is taken as an address, the rest is not a command.
  client.send(Bytes{0x00, 0xFF, 0x13, '\r', '\n'});
  CHECK(number(client.ask(nine_bit_read_sensor_request(5))) == 1001);
  CHECK(bus.sim->counters().malformed == 1);
  // Part of a command, then silence: the next byte is an address again.
  client.send(Bytes{5, '3', '1'});
  CHECK_FALSE(client.line(200ms).has_value());
  CHECK(number(client.ask(nine_bit_read_eeprom_request(5, 16))) == 5);
  CHECK(bus.sim->counters().malformed == 2);
}

TEST_CASE("9-bit: a request written in pieces with a pause after the address is answered") {
  Bus bus(Protocol::nine_bit, {dyna(9)});
  BusClient client(bus.io, bus.sim->link_path());
  client.send(Bytes{9});  // the serial line drains the address byte before the body
  CHECK_FALSE(client.line(100ms).has_value());
  client.send("A\r\n");
  const auto reply = client.line();
  REQUIRE(reply.has_value());
  CHECK(number(*reply) == 1001);
  CHECK(bus.sim->counters().malformed == 0);
}

TEST_CASE("9-bit: injected garbage and silence reach the wire") {
  Bus bus(Protocol::nine_bit, {dyna(0)});
  BusClient client(bus.io, bus.sim->link_path());
  auto& faults = bus.sim->sensor(0).faults();
  faults.garbage = 1;
  CHECK(number(client.ask(nine_bit_read_sensor_request(0))) == 1001);
  CHECK(client.lines().counters().bytes_dropped == faults.garbage_bytes.size());
  faults.silent = 1;
  client.send(nine_bit_read_sensor_request(0));
  CHECK_FALSE(client.line(kSilence).has_value());
  CHECK(number(client.ask(nine_bit_read_sensor_request(0))) == 1001);
}

TEST_CASE("Modbus-ASCII: the simulator answers every command over a pseudo-terminal") {
  Bus bus(Protocol::modbus_ascii, {dyna(2)});
  BusClient client(bus.io, bus.sim->link_path());
  const auto sensor = ascii_read_sensor_request(2);
  CHECK(*parse_ascii_sensor_reply(client.exchange(sensor), *sensor) == 1001);
  const auto temperature = ascii_read_temperature_request(2);
  CHECK(*parse_ascii_temperature_reply(client.exchange(temperature), *temperature) == -40);
  const auto revision = ascii_revision_request(2);
  CHECK(*parse_ascii_revision_reply(client.exchange(revision), *revision) == "01.07");
  // The note's write example, and its documented reply byte for byte.
  client.send(":0268006401639C\r\n");
  CHECK(client.frame() == AsciiFrame{2, 0x68, {}});
  CHECK(std::string(client.raw().end() - 9, client.raw().end()) == ":026830\r\n");
  const auto eeprom = ascii_read_eeprom_request(2, 100);
  CHECK(*parse_ascii_eeprom_reply(client.exchange(eeprom), *eeprom) == 355);
  const auto reset = ascii_reset_request(2);
  CHECK(parse_ascii_ack(client.exchange(reset), *reset).has_value());
  CHECK(bus.sim->sensor(0).resets() == 1);
}

TEST_CASE("Modbus-ASCII: a request with a bad LRC is ignored") {
  Bus bus(Protocol::modbus_ascii, {dyna(1)});
  BusClient client(bus.io, bus.sim->link_path());
  client.send(spectron::test::kPrintedWrite15);  // the note's frame as printed, uppercase F
  CHECK_FALSE(client.frame(kSilence).has_value());
  CHECK(bus.sim->counters().lrc_errors == 1);
  CHECK(bus.sim->sensor(0).eeprom(22) == 10);
  client.send(spectron::test::kLowercaseWrite15);  // as it must have been sent
  CHECK(client.frame() == AsciiFrame{1, 0x68, {}});
  CHECK(bus.sim->sensor(0).eeprom(22) == 15);
}

TEST_CASE("Modbus-ASCII: noise and a cut-short frame before a request do not hide it") {
  Bus bus(Protocol::modbus_ascii, {dyna(20)});
  BusClient client(bus.io, bus.sim->link_path());
  client.send(Bytes{0x00, 0xFF, 'z', ':', '1', '4', '6'});
  client.send(":146900026A\r\n");  // the note's read of location 2 on module 20
  CHECK(client.frame() == make_ascii_word_reply(20, AsciiCommand::read_eeprom, 0));
  CHECK(bus.sim->counters().malformed == 1);
  CHECK(bus.sim->counters().requests_seen == 1);
}

TEST_CASE("Modbus-ASCII: a module answers at its new address after a write to location 16") {
  Bus bus(Protocol::modbus_ascii, {dyna(1), dyna(2, 2002)});
  BusClient client(bus.io, bus.sim->link_path());
  const auto move = ascii_write_eeprom_request(1, 16, 30);
  CHECK(parse_ascii_ack(client.exchange(move), *move).has_value());  // from the old address
  client.send(ascii_read_sensor_request(1));
  CHECK_FALSE(client.frame(kSilence).has_value());
  const auto moved = ascii_read_sensor_request(30);
  CHECK(*parse_ascii_sensor_reply(client.exchange(moved), *moved) == 1001);
  const auto other = ascii_read_sensor_request(2);
  CHECK(*parse_ascii_sensor_reply(client.exchange(other), *other) == 2002);
}

TEST_CASE("Modbus-ASCII: a corrupted reply LRC reaches the wire and is counted") {
  Bus bus(Protocol::modbus_ascii, {dyna(1)});
  BusClient client(bus.io, bus.sim->link_path());
  bus.sim->sensor(0).faults().corrupt_lrc = 1;
  client.send(ascii_read_sensor_request(1));
  CHECK_FALSE(client.frame(kSilence).has_value());
  CHECK(client.frames().counters().lrc_errors == 1);
  CHECK(client.exchange(ascii_read_sensor_request(1)).command == 0x66);
}

namespace {

// One transaction through the real serial line on the simulator's link, as the driver runs it.
bool transact_on_serial_line(Bus& bus, Framing framing, LineRequest request) {
  SerialLineOptions options;
  options.name = "dyna";
  options.port = bus.sim->link_path();
  options.baud = 28800;
  options.timeout = 1000ms;  // generous: the machine may be busy
  options.framing = framing;
  tiltgate::test::skip_unless_settable(options);
  SerialLine line(bus.io.get_executor(), options);
  REQUIRE(line.start());
  const bool replied =
      tiltgate::test::run_coroutine(bus.io, line.transact(std::move(request))).has_value();
  line.stop();
  return replied;
}

}  // namespace

TEST_CASE("a serial line in 9-bit framing gets its reply from the simulator") {
  Bus bus(Protocol::nine_bit, {dyna(7)});
  NineBitReplyFramer framer;
  LineRequest request;
  request.bytes = wire_bytes(nine_bit_read_eeprom_request(7, 4).value());
  request.address_bytes = kNineBitAddressBytes;  // mark parity, then space for the body
  request.framer = &framer;
  CHECK(transact_on_serial_line(bus, Framing::nine_bit, std::move(request)));
  REQUIRE(framer.reply().has_value());
  CHECK(number(*framer.reply()) == 12345);
}

TEST_CASE("a serial line in 8E1 framing gets its Modbus-ASCII reply from the simulator") {
  Bus bus(Protocol::modbus_ascii, {dyna(3)});
  const AsciiFrame read = *ascii_read_temperature_request(3);
  AsciiReplyFramer framer(read);
  LineRequest request;
  request.bytes = encode(read);
  request.framer = &framer;
  CHECK(transact_on_serial_line(bus, Framing::eight_even_one, std::move(request)));
  REQUIRE(framer.reply().has_value());
  CHECK(*parse_ascii_temperature_reply(*framer.reply(), read) == -40);
}

TEST_CASE("unplug removes the link and replug serves a new pty behind it, state kept") {
  Bus bus(Protocol::modbus_ascii, {dyna(1)});
  const std::string link = bus.sim->link_path();
  CHECK(std::filesystem::read_symlink(link) == bus.sim->slave_path());
  {
    BusClient client(bus.io, link);
    client.exchange(ascii_write_eeprom_request(1, 6, 1));
    bus.sim->unplug();
    CHECK_FALSE(bus.sim->plugged());
    CHECK(bus.sim->slave_path().empty());
    CHECK_FALSE(std::filesystem::exists(std::filesystem::symlink_status(link)));
    int error = 0;
    const ssize_t n = client.read_once(error);
    CHECK(n <= 0);
    if (n < 0) CHECK(error == EIO);
  }
  REQUIRE(bus.sim->replug().has_value());
  CHECK(std::filesystem::read_symlink(link) == bus.sim->slave_path());
  BusClient client(bus.io, link);
  const auto read = ascii_read_sensor_request(1);
  CHECK(*parse_ascii_sensor_reply(client.exchange(read), *read) == 1000);  // offset kept
}

TEST_CASE("Spectron: replies paced at a baud rate take at least their transmission time") {
  // "12345\r\n" is 7 bytes; at 1200 baud, 11 bits a byte: 64 ms. Only the lower bound is
  // checked; a busy machine can only make it longer.
  Bus bus(Protocol::nine_bit, {dyna(0)}, 1200);
  BusClient client(bus.io, bus.sim->link_path());
  const auto sent = std::chrono::steady_clock::now();
  CHECK(number(client.ask(nine_bit_read_eeprom_request(0, 4))) == 12345);
  CHECK(std::chrono::steady_clock::now() - sent >= 64ms);
}

TEST_CASE("Spectron: stopping the simulator with a reply still pending is safe") {
  Bus bus(Protocol::nine_bit, {dyna(0)}, 1200);  // the reply waits ~64 ms on its timer
  BusClient client(bus.io, bus.sim->link_path());
  client.send(nine_bit_read_eeprom_request(0, 4));
  REQUIRE(run_until(bus.io, [&] { return bus.sim->counters().requests_seen == 1; }));
  bus.sim.reset();
  bus.io.restart();
  bus.io.run_for(100ms);
  CHECK_FALSE(client.line(50ms).has_value());
}
