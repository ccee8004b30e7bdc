// What `tiltgate check` warns a warm standby pair of (config/redundancy_warnings.h): a bus it
// cannot listen to (a device server's, Modbus TCP devices'), a bus with no polls to hear (pass
// through only), a 9-bit bus heard without its 9th bit; nothing without [redundancy].
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "config/config_loader.h"
#include "config/redundancy_warnings.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

constexpr std::string_view kStandby = "[redundancy]\nrole = \"standby\"\npeer = \"gw-a:502\"\n";

std::vector<std::string> warnings_of(const std::string& text) {
  return redundancy_warnings(loads(text), registered_families());
}

// The valid base (a Rieker bus "line1" with one sensor) and `more`, as a standby's file.
std::string standby_plus(std::string_view more) {
  return std::string(kStandby) + valid_plus(more);
}

}  // namespace

TEST_CASE("redundancy warnings: none for a local bus with sensors, none without [redundancy]") {
  CHECK(warnings_of(standby_plus("")).empty());
  std::string behind_server = valid_plus("");
  behind_server.replace(behind_server.find("/dev/ttyUSB0"), 12, "tcp://192.168.1.20:4001");
  CHECK(warnings_of(behind_server).empty());
}

TEST_CASE("redundancy warnings: a bus behind a device server cannot be listened to") {
  std::string text = standby_plus("");
  text.replace(text.find("/dev/ttyUSB0"), 12, "tcp://192.168.1.20:4001");
  CHECK(warnings_of(text) ==
        std::vector<std::string>{
            "bus \"line1\" is behind a device server (\"tcp://192.168.1.20:4001\"): a standby "
            "cannot listen to it; it opens it only when it takes over"});
}

TEST_CASE("redundancy warnings: a bus of Modbus TCP devices cannot be listened to") {
  const std::vector<std::string> warnings = warnings_of(standby_plus(
      "[[bus]]\nname = \"plc\"\nport = \"tcp://10.0.0.9:502\"\nprotocol = \"modbus-tcp\"\n"
      "pass_through = [40]\n"));
  CHECK(warnings == std::vector<std::string>{
                        "bus \"plc\" reaches its devices over TCP (\"tcp://10.0.0.9:502\"): a "
                        "standby cannot listen to it; it connects only when it takes over"});
}

TEST_CASE("redundancy warnings: a pass-through-only bus carries no requests to hear") {
  const std::vector<std::string> warnings = warnings_of(standby_plus(
      "[[bus]]\nname = \"rtu\"\nport = \"/dev/ttyUSB5\"\nprotocol = \"modbus-rtu\"\n"
      "pass_through = [30]\n"));
  CHECK(warnings == std::vector<std::string>{
                        "bus \"rtu\" has no sensors (pass-through only): it carries no regular "
                        "requests, so a standby cannot tell from it that the primary is alive"});
}

TEST_CASE("redundancy warnings: a 9-bit bus is heard without its 9th bit") {
  const std::vector<std::string> warnings =
      warnings_of(std::string(kStandby) + dyna_bus("spectron-9bit", "baud = 9600\n") +
                  dyna_sensor(5));
  CHECK(warnings == std::vector<std::string>{
                        "bus \"s\" is spectron-9bit: a standby hears its address bytes without "
                        "their 9th bit; it still follows the line, telling requests from replies "
                        "by their form, with no checksum to confirm them (docs/diagnostics.md, "
                        "\"Listening only\")"});
  CHECK(warnings_of(std::string(kStandby) + dyna_bus("spectron-modbus", "baud = 9600\n") +
                    dyna_sensor(5))
            .empty());
}
