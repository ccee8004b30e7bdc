// The control socket's messages (control/control_protocol.h): each formats to the documented
// line and parses back to itself; anything else is refused with a message, never guessed at.
#include <doctest/doctest.h>

#include <optional>
#include <string>
#include <vector>

#include "control/control_protocol.h"

using namespace tiltgate;
using namespace tiltgate::control;
using namespace std::chrono_literals;

TEST_CASE("control: a transaction request formats as documented and parses back") {
  const Transact request{1, 50ms, 0, 20ms, true, 30ms, {0x05, 0x41, 0x0D, 0x0A}};
  const std::string line = format(CommandMessage{request});
  CHECK(line == "transact 1 50 0 20 1 30 05410D0A");
  auto parsed = parse_command(line);
  REQUIRE(parsed);
  const auto* back = std::get_if<Transact>(&*parsed);
  REQUIRE(back != nullptr);
  CHECK(back->address_bytes == 1);
  CHECK(back->timeout == 50ms);
  CHECK(back->retries == 0);
  CHECK(back->settle == 20ms);
  CHECK(back->expects_reply);
  CHECK(back->late_guard == 30ms);
  CHECK(back->bytes == request.bytes);
  auto bus_guard = parse_command("transact 0 50 -1 0 0 - 01");
  REQUIRE(bus_guard);
  CHECK_FALSE(std::get<Transact>(*bus_guard).late_guard.has_value());
  CHECK(std::get<Transact>(*bus_guard).retries == -1);
  CHECK_FALSE(std::get<Transact>(*bus_guard).expects_reply);
}

TEST_CASE("control: hello keeps a port path whole, follow carries both addresses") {
  auto hello = parse_command("hello /dev/serial/by-id/usb-FTDI adapter");
  REQUIRE(hello);
  CHECK(std::get<Hello>(*hello).port == "/dev/serial/by-id/usb-FTDI adapter");
  auto follow = parse_command(format(CommandMessage{Follow{223, 7}}));
  REQUIRE(follow);
  CHECK(std::get<Follow>(*follow).from == 223);
  CHECK(std::get<Follow>(*follow).to == 7);
  CHECK(std::get<Hold>(*parse_command(format(CommandMessage{Hold{223}}))).address == 223);
  CHECK(std::get<Release>(*parse_command("release 223")).address == 223);
  CHECK(std::get<FramerAnswer>(*parse_command("done")).done);
  CHECK_FALSE(std::get<FramerAnswer>(*parse_command("more")).done);
}

TEST_CASE("control: a setting the sensor acknowledged carries its address, id and value") {
  CHECK(format(CommandMessage{SettingChanged{223, 1, -0.25, std::nullopt, false}}) == "setting 223 1 -0.25");
  auto changed = parse_command("setting 223 1 -0.25");
  REQUIRE(changed);
  CHECK(std::get<SettingChanged>(*changed).address == 223);
  CHECK(std::get<SettingChanged>(*changed).setting == 1);
  CHECK(std::get<SettingChanged>(*changed).value == -0.25);
  CHECK_FALSE(parse_command("setting 223 300 2"));  // no such id
  CHECK_FALSE(parse_command("setting 223 0 nan"));
  CHECK_FALSE(parse_command("setting 223 0"));
}

TEST_CASE("control: a setting the sensor refused or left unanswered says so, and `as` names someone") {
  SettingChanged refused{223, 0, 2, std::nullopt, false};
  refused.nak = 3;
  CHECK(format(CommandMessage{refused}) == "setting 223 0 2 nak 3");
  SettingChanged unanswered{223, 0, 2, std::nullopt, false};
  unanswered.timeout = true;
  CHECK(format(CommandMessage{unanswered}) == "setting 223 0 2 timeout");
  auto nak = parse_command("setting 223 0 2 nak 3");
  REQUIRE(nak);
  CHECK(std::get<SettingChanged>(*nak).nak == std::optional<std::uint8_t>(3));
  CHECK_FALSE(std::get<SettingChanged>(*nak).timeout);
  auto timeout = parse_command("setting 223 0 2 timeout");
  REQUIRE(timeout);
  CHECK(std::get<SettingChanged>(*timeout).timeout);
  CHECK_FALSE(std::get<SettingChanged>(*timeout).nak.has_value());
  auto ack = parse_command("setting 223 0 2");
  REQUIRE(ack);
  CHECK_FALSE(std::get<SettingChanged>(*ack).nak.has_value());
  CHECK_FALSE(std::get<SettingChanged>(*ack).timeout);
  CHECK_FALSE(parse_command("setting 223 0 2 nak"));
  CHECK_FALSE(parse_command("setting 223 0 2 nak 300"));
  CHECK_FALSE(parse_command("setting 223 0 2 late"));
  CHECK(format(CommandMessage{ActingFor{"console user alice"}}) == "as console user alice");
  auto as = parse_command("as console user alice");
  REQUIRE(as);
  CHECK(std::get<ActingFor>(*as).who == "console user alice");
  CHECK_FALSE(parse_command("as"));
}

TEST_CASE("control: both ends say their version first, and a mismatch is one line naming both") {
  CHECK(format(CommandMessage{Version{2, "0.1.0"}}) == "version 2 0.1.0");
  CHECK(format(GatewayMessage{Version{2, "0.1.0"}}) == "version 2 0.1.0");
  auto said = parse_command("version 2 0.1.0");
  REQUIRE(said);
  CHECK(std::get<Version>(*said).protocol == 2);
  CHECK(std::get<Version>(*said).product == "0.1.0");
  CHECK(std::get<Version>(*parse_gateway("version 3 1.0.0")).protocol == 3);
  CHECK_FALSE(parse_command("version two 0.1.0"));
  CHECK_FALSE(parse_command("version 2"));
  // Protocol 1 commands show any line they cannot read as it is: the mismatch is not "error".
  const std::string to_old = version_mismatch("0.2.0", std::nullopt);
  CHECK(to_old.starts_with("version 2 0.2.0: this gateway (tiltgate 0.2.0) speaks control "
                           "protocol 2, this command (an older tiltgate) speaks control protocol 1"));
  CHECK_FALSE(parse_gateway(to_old));  // nor a version line a newer command would take
  CHECK(version_mismatch("0.2.0", Version{3, "0.3.0"}).find(
            "this command (tiltgate 0.3.0) speaks control protocol 3") != std::string::npos);
  CHECK(older_gateway("0.2.0") ==
        "the running gateway speaks control protocol 1 (an older tiltgate), this command "
        "(tiltgate 0.2.0) speaks control protocol 2: run the tiltgate of the gateway's own version");
}

TEST_CASE("control: the gateway's end of a transaction carries its outcome, timing and generation") {
  Ended ok;
  ok.timing.reply_delay = 3ms;
  ok.generation = 4;
  CHECK(format(GatewayMessage{ok}) == "end ok 3 0 - 4");
  auto back = parse_gateway("end ok 3 0 - 4");
  REQUIRE(back);
  const Ended& ended = std::get<Ended>(*back);
  CHECK_FALSE(ended.error);
  CHECK(ended.timing.reply_delay == 3ms);
  CHECK(ended.generation == 4);

  Ended late;
  late.error = LineError::timeout;
  late.timing.late_replies = 1;
  late.timing.late_delay = 120ms;
  auto timed_out = parse_gateway(format(GatewayMessage{late}));
  REQUIRE(timed_out);
  CHECK(std::get<Ended>(*timed_out).error == LineError::timeout);
  CHECK(std::get<Ended>(*timed_out).timing.late_delay == 120ms);

  Ended busy;
  busy.busy = true;
  auto never_sent = parse_gateway(format(GatewayMessage{busy}));
  REQUIRE(never_sent);
  CHECK(std::get<Ended>(*never_sent).busy);
  CHECK(std::get<Ended>(*never_sent).error == LineError::timeout);
}

TEST_CASE("control: received bytes, the bus granted and a refusal parse back") {
  auto bytes = parse_gateway(format(GatewayMessage{Received{{0x00, 0xDF, 0xAF, 0x11}}}));
  REQUIRE(bytes);
  CHECK(std::get<Received>(*bytes).bytes == std::vector<std::uint8_t>{0x00, 0xDF, 0xAF, 0x11});
  auto bus = parse_gateway(format(GatewayMessage{BusGranted{"line1", "binary", 125000}}));
  REQUIRE(bus);
  CHECK(std::get<BusGranted>(*bus).name == "line1");
  CHECK(std::get<BusGranted>(*bus).baud == 125000);
  auto refused = parse_gateway("error the gateway has no bus on /dev/ttyS9");
  REQUIRE(refused);
  CHECK(std::get<Refused>(*refused).reason == "the gateway has no bus on /dev/ttyS9");
}

TEST_CASE("control: malformed lines are refused") {
  for (const char* line :
       {"", "hello", "transact 0 50 2 0 1 -", "transact 0 50 2 0 1 - 0",
        "transact 0 50 2 0 1 - ZZ", "transact 3 50 2 0 1 - 0102", "transact 0 -5 2 0 1 - 01",
        "transact 0 50 -2 0 1 - 01", "transact 0 50 2 0 7 - 01", "transact 0 50 2 0 1 x 01",
        "transact 0 50 2 0 1 01", "transact 0 50 2 0 1 - ", "follow 1", "follow a b", "more please",
        "rm -rf /"}) {
    CAPTURE(line);
    CHECK_FALSE(parse_command(line));
  }
  for (const char* line : {"", "end ok", "end maybe 1 0 - 1", "bytes 0", "bus line1 p x", "hi"}) {
    CAPTURE(line);
    CHECK_FALSE(parse_gateway(line));
  }
}
