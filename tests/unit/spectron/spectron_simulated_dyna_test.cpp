// The simulated Dyna answers both protocols as the note describes (with the reply formats of
// spectron/assumptions.h): reads, writes, address changes, reset, faults. No I/O.
#include <doctest/doctest.h>

#include "spectron/ascii_frame_parser.h"
#include "spectron/nine_bit_codec.h"
#include "spectron/sensor_spec.h"
#include "spectron/simulated_dyna.h"
#include "unit/spectron/spectron_test_vectors.h"

using namespace tiltgate::spectron;
using test::bytes;

namespace {

const SimTime kT0{0.0};

SimulatedDyna dyna(std::uint8_t address) {
  SimulatedDynaOptions options;
  options.address = address;
  options.counts = 1001;
  options.temperature = -40;
  return SimulatedDyna(options);
}

// The 9-bit reply text without CR LF, or nullopt for silence.
std::optional<std::string> nine_bit(SimulatedDyna& sensor, std::uint8_t address,
                                    std::string_view body, SimTime now = kT0) {
  const auto reply = sensor.respond_nine_bit(address, body, now);
  if (!reply) return std::nullopt;
  const std::string text(reply->begin(), reply->end());
  REQUIRE(text.size() >= 2);
  REQUIRE(text.substr(text.size() - 2) == "\r\n");
  return text.substr(0, text.size() - 2);
}

// The Modbus-ASCII reply, decoded, or nullopt for silence.
std::optional<AsciiFrame> ascii(SimulatedDyna& sensor, const AsciiRequestResult& request) {
  REQUIRE(request.has_value());
  const auto reply = sensor.respond_ascii(*request, kT0);
  if (!reply) return std::nullopt;
  const auto frame = decode(std::string_view(reinterpret_cast<const char*>(reply->data()),
                                             reply->size()));
  REQUIRE(frame.has_value());
  return *frame;
}

}  // namespace

TEST_CASE("9-bit: the module answers reads in decimal and acknowledges with an empty line") {
  SimulatedDyna sensor = dyna(0);
  CHECK(nine_bit(sensor, 0, "A") == "1001");
  CHECK(nine_bit(sensor, 0, "C") == "-40");
  CHECK(nine_bit(sensor, 0, "F") == "DYNA 1.07");
  CHECK(nine_bit(sensor, 0, "34") == "12345");  // the serial number
  CHECK(nine_bit(sensor, 0, "322") == "10");     // baud code 28800
  CHECK(nine_bit(sensor, 0, "E6,1") == "");
  CHECK(nine_bit(sensor, 0, "36") == "1");
  CHECK(nine_bit(sensor, 0, "A") == "1000");  // the offset is subtracted at once
  CHECK(nine_bit(sensor, 0, "E10 65535") == "");  // -1 as a signed word
  CHECK(nine_bit(sensor, 0, "C") == "-39");
  CHECK(nine_bit(sensor, 0, "0") == "");
  CHECK(sensor.resets() == 1);
  CHECK(sensor.requests_handled() == 11);
}

TEST_CASE("9-bit: other addresses, unknown commands and refused writes get silence") {
  SimulatedDyna sensor = dyna(0);
  CHECK_FALSE(nine_bit(sensor, 1, "A").has_value());
  CHECK_FALSE(nine_bit(sensor, 0, "B").has_value());
  CHECK_FALSE(nine_bit(sensor, 0, "35").has_value());       // odd
  CHECK_FALSE(nine_bit(sensor, 0, "3282").has_value());     // past the EEPROM
  CHECK_FALSE(nine_bit(sensor, 0, "E22,8").has_value());    // not a baud code
  CHECK_FALSE(nine_bit(sensor, 0, "E34;2501").has_value()); // not a delimiter
  CHECK(sensor.eeprom(22) == 10);
  // The note's write example: location 34 exists in the simulated EEPROM.
  CHECK(nine_bit(sensor, 0, "E34,2501") == "");
  CHECK(sensor.eeprom(34) == 2501);
}

TEST_CASE("9-bit: after a write to location 16 the module answers at the new address") {
  SimulatedDyna sensor = dyna(0);
  CHECK(nine_bit(sensor, 0, "E16,255") == "");
  CHECK(sensor.address() == 255);
  CHECK_FALSE(nine_bit(sensor, 0, "A").has_value());
  CHECK(nine_bit(sensor, 255, "316") == "255");
}

TEST_CASE("a new baud code takes effect at reset, which re-reads the EEPROM") {
  SimulatedDyna sensor = dyna(3);
  CHECK(nine_bit(sensor, 3, "E22,64") == "");
  CHECK(sensor.baud_code() == 10);
  CHECK(nine_bit(sensor, 3, "0") == "");
  CHECK(sensor.baud_code() == 64);
  sensor.reset();  // a power cycle keeps the EEPROM
  CHECK(sensor.baud_code() == 64);
  CHECK(sensor.address() == 3);
}

TEST_CASE("Modbus-ASCII: the module answers with one word per read (A6) and echoes writes") {
  SimulatedDyna sensor = dyna(2);
  CHECK(*parse_ascii_sensor_reply(*ascii(sensor, ascii_read_sensor_request(2)),
                                  *ascii_read_sensor_request(2)) == 1001);
  CHECK(*parse_ascii_temperature_reply(*ascii(sensor, ascii_read_temperature_request(2)),
                                       *ascii_read_temperature_request(2)) == -40);
  CHECK(*parse_ascii_revision_reply(*ascii(sensor, ascii_revision_request(2)),
                                    *ascii_revision_request(2)) == "01.07");
  // The note's write example and its reply, byte for byte.
  const auto write = sensor.respond_ascii(*decode(":0268006401639C\r\n"), kT0);
  REQUIRE(write.has_value());
  CHECK(*write == bytes(":026830\r\n"));
  CHECK(*parse_ascii_eeprom_reply(*ascii(sensor, ascii_read_eeprom_request(2, 100)),
                                  *ascii_read_eeprom_request(2, 100)) == 355);
  CHECK(ascii(sensor, ascii_reset_request(2)) == make_ascii_ack(2, AsciiCommand::reset));
  CHECK(sensor.resets() == 1);
}

TEST_CASE("Modbus-ASCII: the address change is answered from the old address") {
  SimulatedDyna sensor = dyna(1);
  CHECK(ascii(sensor, ascii_write_eeprom_request(1, 16, 250)) ==
        make_ascii_ack(1, AsciiCommand::write_eeprom));
  CHECK(sensor.address() == 250);
  CHECK_FALSE(ascii(sensor, ascii_read_sensor_request(1)).has_value());
  CHECK(ascii(sensor, ascii_read_sensor_request(250)).has_value());
  // 0 and 251.. are not Modbus-ASCII addresses: refused.
  CHECK_FALSE(sensor.respond_ascii(AsciiFrame{250, 0x68, {0x00, 0x10, 0x00, 0x00}}, kT0));
  CHECK(sensor.address() == 250);
}

TEST_CASE("Modbus-ASCII: unknown commands and wrong data lengths get silence") {
  SimulatedDyna sensor = dyna(1);
  CHECK_FALSE(sensor.respond_ascii(AsciiFrame{1, 0x03, {}}, kT0));
  CHECK_FALSE(sensor.respond_ascii(AsciiFrame{1, 0x66, {0x00}}, kT0));
  CHECK_FALSE(sensor.respond_ascii(AsciiFrame{1, 0x69, {0x00, 0x03}}, kT0));  // odd location
  CHECK(sensor.requests_handled() == 1);  // only the well-formed read of location 3
}

TEST_CASE("faults of one command apply to it in both protocols, and to no other") {
  using namespace std::chrono_literals;
  SimulatedDyna sensor = dyna(1);
  CommandFaults& read_sensor = sensor.faults().by_command[AsciiCommand::read_sensor];
  read_sensor.silent = 2;
  read_sensor.delay = 120ms;
  CHECK_FALSE(ascii(sensor, ascii_read_sensor_request(1)).has_value());
  CHECK_FALSE(sensor.respond_nine_bit(1, "A", kT0).has_value());  // "A" is read sensor
  CHECK(sensor.respond_nine_bit(1, "C", kT0).has_value());
  CHECK(ascii(sensor, ascii_read_sensor_request(1)).has_value());
  CHECK(sensor.reply_delay(AsciiCommand::read_sensor) == 120ms);
  CHECK(sensor.reply_delay(AsciiCommand::read_temperature) == 0ms);
}

TEST_CASE("injected faults: silence, a corrupted LRC, garbage before the reply") {
  SimulatedDyna sensor = dyna(1);
  auto& faults = sensor.faults();
  faults.silent = 1;
  CHECK_FALSE(ascii(sensor, ascii_read_sensor_request(1)).has_value());
  CHECK(ascii(sensor, ascii_read_sensor_request(1)).has_value());

  faults.corrupt_lrc = 1;
  const auto damaged = sensor.respond_ascii(*ascii_read_sensor_request(1), kT0);
  REQUIRE(damaged.has_value());
  AsciiFrameParser parser;
  CHECK(parser.feed(*damaged) == 0);
  CHECK(parser.counters().lrc_errors == 1);

  faults.garbage = 1;
  const auto noisy = sensor.respond_nine_bit(1, "A", kT0);
  REQUIRE(noisy.has_value());
  CHECK(noisy->size() == faults.garbage_bytes.size() + 6);
  NineBitLineParser lines;
  CHECK(lines.feed(*noisy) == 1);
  CHECK(lines.next() == "1001");
}

TEST_CASE("the reading sways with time when asked to, and can be fixed") {
  SimulatedDynaOptions options;
  options.counts = 1000;
  options.sway_amplitude = 100.0;
  options.sway_period_s = 40.0;
  SimulatedDyna sensor(options);
  CHECK(sensor.counts(SimTime{0.0}) == 1000);
  CHECK(sensor.counts(SimTime{10.0}) == 1100);
  CHECK(sensor.counts(SimTime{30.0}) == 900);
  sensor.set_counts(-32768);
  CHECK(sensor.counts(SimTime{10.0}) == -32768);
  sensor.set_temperature(20);
  CHECK(sensor.temperature() == 20);
}

TEST_CASE("the sensor list gives each module its protocol's default and range of address") {
  const auto nine = parse_sensor_spec("dyna, DYNA:7 ,dyna:255", Protocol::nine_bit);
  REQUIRE(nine.has_value());
  REQUIRE(nine->size() == 3);
  CHECK((*nine)[0].address == 0);
  CHECK((*nine)[1].address == 7);
  CHECK((*nine)[2].address == 255);
  CHECK((*nine)[1].serial == 10007);
  CHECK((*nine)[1].counts == 2000);
  const auto modbus = parse_sensor_spec("dyna,dyna:2", Protocol::modbus_ascii);
  REQUIRE(modbus.has_value());
  CHECK((*modbus)[0].address == 1);
  CHECK((*modbus)[1].address == 2);

  CHECK(parse_sensor_spec("dyna:0", Protocol::modbus_ascii).error() ==
        "sensor 'dyna:0': address must be 1..250 on a Modbus-ASCII bus");
  CHECK(parse_sensor_spec("dyna:256", Protocol::nine_bit).error() ==
        "sensor 'dyna:256': address must be 0..255 on a 9-bit bus");
  CHECK(parse_sensor_spec("h6:1", Protocol::nine_bit).error() ==
        "sensor 'h6:1': model must be dyna");
  CHECK(parse_sensor_spec("dyna:1,dyna:1", Protocol::nine_bit).error() ==
        "sensor 'dyna:1': address 1 is used twice");
  CHECK(parse_sensor_spec("dyna,,dyna:2", Protocol::nine_bit).error() ==
        "empty sensor in the sensor list");
  CHECK(parse_sensor_spec("dyna:x", Protocol::nine_bit).has_value() == false);
}
