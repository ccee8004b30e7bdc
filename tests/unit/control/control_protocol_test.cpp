// The control socket's messages (control/control_protocol.h): each formats to the documented
// line and parses back to itself; anything else is refused with a message, never guessed at.
#include <doctest/doctest.h>

#include <optional>
#include <string>
#include <vector>

#include "control/control_protocol.h"

using namespace tiltgate;
using namespace tiltgate::control;

TEST_CASE("control: hello keeps a port path whole, and a run carries its request as it is") {
  auto hello = parse_command(format(CommandMessage{Hello{"/dev/serial/by-id/usb-FTDI port 0"}}));
  REQUIRE(hello);
  CHECK(std::get<Hello>(*hello).port == "/dev/serial/by-id/usb-FTDI port 0");
  const std::string request = R"({"command":"scan","bus":{"port":"/dev/ttyUSB0"}})";
  CHECK(format(CommandMessage{Run{request}}) == "run " + request);
  auto run = parse_command("run " + request);
  REQUIRE(run);
  CHECK(std::get<Run>(*run).request == request);
  CHECK(format(CommandMessage{Stop{}}) == "stop");
  CHECK(std::holds_alternative<Stop>(*parse_command("stop")));
}

TEST_CASE("control: both ends say their version first, and a mismatch is one line naming both") {
  CHECK(format(CommandMessage{Version{3, "0.1.0"}}) == "version 3 0.1.0");
  CHECK(format(GatewayMessage{Version{3, "0.1.0"}}) == "version 3 0.1.0");
  auto said = parse_command("version 3 0.1.0");
  REQUIRE(said);
  CHECK(std::get<Version>(*said).protocol == 3);
  CHECK(std::get<Version>(*said).product == "0.1.0");
  CHECK(std::get<Version>(*parse_gateway("version 4 1.0.0")).protocol == 4);
  CHECK_FALSE(parse_command("version two 0.1.0"));
  CHECK_FALSE(parse_command("version 3"));
  // Protocol 1 commands show any line they cannot read as it is: the mismatch is not "error".
  const std::string to_old = version_mismatch("0.2.0", std::nullopt);
  CHECK(to_old.starts_with("version 3 0.2.0: this gateway (tiltgate 0.2.0) speaks control "
                           "protocol 3, this command (an older tiltgate) speaks control protocol 1"));
  CHECK_FALSE(parse_gateway(to_old));  // nor a version line a newer command would take
  CHECK(version_mismatch("0.2.0", Version{2, "0.1.9"}).find(
            "this command (tiltgate 0.1.9) speaks control protocol 2") != std::string::npos);
  CHECK(older_gateway("0.2.0") ==
        "the running gateway speaks control protocol 1 (an older tiltgate), this command "
        "(tiltgate 0.2.0) speaks control protocol 3: run the tiltgate of the gateway's own version");
}

TEST_CASE("control: the bus granted, a refusal, an event and the exit code parse back") {
  auto bus = parse_gateway(format(GatewayMessage{BusGranted{"line1", "binary", 125000}}));
  REQUIRE(bus);
  CHECK(std::get<BusGranted>(*bus).name == "line1");
  CHECK(std::get<BusGranted>(*bus).baud == 125000);
  auto refused = parse_gateway("error the gateway has no bus on /dev/ttyS9");
  REQUIRE(refused);
  CHECK(std::get<Refused>(*refused).reason == "the gateway has no bus on /dev/ttyS9");
  const std::string json = R"({"event":"note","warning":false,"text":"a b  c"})";
  CHECK(format(GatewayMessage{Event{json}}) == "event " + json);
  auto event = parse_gateway("event " + json);
  REQUIRE(event);
  CHECK(std::get<Event>(*event).json == json);
  CHECK(format(GatewayMessage{Exit{2}}) == "exit 2");
  auto exit = parse_gateway("exit 2");
  REQUIRE(exit);
  CHECK(std::get<Exit>(*exit).code == 2);
}

TEST_CASE("control: malformed lines are refused") {
  for (const char* line : {"", "hello", "run", "stop now", "transact 0 50 2 0 1 - 01",
                           "follow 1 2", "setting 223 0 2", "as console user alice", "rm -rf /"}) {
    CAPTURE(line);
    CHECK_FALSE(parse_command(line));
  }
  for (const char* line : {"", "event", "exit", "exit -1", "exit 256", "exit x", "end ok 1 0 - 1",
                           "bytes 00", "bus line1 p x", "hi"}) {
    CAPTURE(line);
    CHECK_FALSE(parse_gateway(line));
  }
}
