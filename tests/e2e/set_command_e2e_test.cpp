// `tiltgate set` against `tiltgate sim FAMILY` on a pseudo-terminal: a re-address the sensor
// follows, a taken address refused with nothing sent, zeroing, a Dyna EEPROM write read back, a
// sensor's NAK shown with its meaning, a silent address, values refused before sending, a baud
// change the line follows, and the configuration file updated in place.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "e2e/support/front_end.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/output_checks.h"
#include "e2e/support/simulator_process.h"

using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

double info_value(const std::string& out, const std::string& label) {
  std::istringstream in(out);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(label + ":", 0) == 0) return std::stod(line.substr(label.size() + 1));
  FAIL("no line " << label << " in:\n" << out);
  return 0;
}

// `tiltgate COMMAND --port TTY --protocol rieker ARGS...`
CommandResult rieker(const std::string& command, const SimulatorProcess& sim,
                     std::vector<std::string> args) {
  std::vector<std::string> all{command, "--port", sim.tty(), "--protocol", "rieker"};
  all.insert(all.end(), args.begin(), args.end());
  return run_command(all);
}

CommandResult set_on(const SimulatorProcess& sim, std::vector<std::string> args) {
  return rieker("set", sim, std::move(args));
}

CommandResult info_at(const SimulatorProcess& sim, const std::string& address) {
  return rieker("info", sim, {"--address", address});
}

}  // namespace

TEST_CASE("set address moves a factory sensor from 223 to 7: it answers at 7 and no more at 223") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223,h6:224"});
  const auto set = run_command({"set", "--port", sim.tty(), "--address", "223", "address", "7"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 0);
  CHECK(has_line(set.out, "the sensor now answers at address 7"));
  CHECK(has_line(set.out, "address:    7"));  // read back at the new address
  CHECK(has_line(set.out, "serial:     9600223"));
  CHECK(info_at(sim, "7").exit_code == 0);
  CHECK(info_at(sim, "223").exit_code == 1);
}

TEST_CASE("set address refuses an address another sensor answers to, and changes nothing") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223,h6:224"});
  const auto set = run_command({"set", "--port", sim.tty(), "--address", "223", "address", "224"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 1);
  CHECK(has(set.err, "address 224 is taken: a sensor already answers there (serial 9600224)"));
  CHECK(has_line(info_at(sim, "223").out, "serial:     9600223"));
  CHECK(has_line(info_at(sim, "224").out, "serial:     9600224"));
}

TEST_CASE("set zero-here zeroes the sensor at its current angle") {
  // The simulator's first sensor sways around X = 1, Y = -1 (+-0.25 deg).
  SimulatorProcess sim({"rieker", "--sensors", "h6:223"});
  REQUIRE(info_value(info_at(sim, "223").out, "angle x") > 0.5);
  const auto set = set_on(sim, {"--address", "223", "zero-here"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 0);
  CHECK(has_line(set.out, "zero-here at address 223: acknowledged"));
  CHECK(std::abs(info_value(set.out, "angle x")) < 0.6);
  CHECK(std::abs(info_value(set.out, "angle y")) < 0.6);
}

TEST_CASE("set zero-here --permanent says so when the sensor acknowledges it") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223"});
  const auto set = set_on(sim, {"--address", "223", "zero-here", "--permanent"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 0);
  CHECK(has_line(set.out, "zero-here --permanent at address 223: acknowledged"));
  CHECK(std::abs(info_value(set.out, "angle x")) < 0.6);
}

TEST_CASE("set shows a sensor's NAK with its meaning from the manual and exits 1") {
  // An H4360 told it is an H6: its Set Zero To Value on axis 2 gets NAK 2.
  SimulatorProcess sim({"rieker", "--sensors", "h4360:101"});
  const auto set = set_on(sim, {"--model", "h6", "--address", "101", "zero-y", "1"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 1);
  CHECK(has(set.err, "zero_y := 1 at address 101: the sensor refused the change"));
  CHECK(has(set.err, "NAK 2 (function not valid for this sensor or mode)"));
}

TEST_CASE("set on a silent address exits 1 with no reply and the hint, sending no change") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223"});
  const auto set = set_on(sim, {"--address", "7", "filter", "2"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 1);
  CHECK(has(set.err, "no reply from address 7 on " + sim.tty()));
  CHECK(has(set.err, "hint:"));
}

TEST_CASE("set refuses a value out of range, or an unknown setting, with exit 2") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223"});
  const auto filter = set_on(sim, {"--address", "223", "filter", "9"});
  INFO(filter.out << filter.err);
  CHECK(filter.exit_code == 2);
  CHECK(has(filter.err, "filter response must be 1..6; nothing was sent"));
  const auto unknown = set_on(sim, {"--address", "223", "adress", "7"});
  CHECK(unknown.exit_code == 2);
  CHECK(has(unknown.err, "did you mean \"address\"?"));
  const auto negative = set_on(sim, {"--address", "223", "zero-x", "-400"});
  CHECK(negative.exit_code == 2);
  CHECK(has(negative.err, "(zero_x accepts -180..180 deg)"));
}

TEST_CASE("set baud restarts the sensor at the new rate and reads it back there") {
  if (skipped_through_gateway("the gateway's bus keeps its rate: the line does not follow the sensor"))
    return;
  SimulatorProcess sim({"rieker", "--sensors", "h6:223"});
  const auto set = set_on(sim, {"--address", "223", "baud", "115200"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 0);
  CHECK(has_line(set.out, "the sensor restarted at 115200 baud; the line follows it"));
  CHECK(has_line(set.out, "serial:     9600223"));
  CHECK(has_line(set.out, "baud_code:  3"));
}

TEST_CASE("set eeprom writes a Dyna's EEPROM location through the window and reads it back") {
  SimulatorProcess sim({"spectron", "--protocol", "modbus", "--sensors", "dyna:1"});
  const auto set = run_command({"set", "--port", sim.tty(), "--protocol", "spectron-modbus",
                                "--baud", "28800", "--address", "1", "eeprom", "20", "1234"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 0);
  CHECK(has_line(set.out, "eeprom_location: 20"));
  CHECK(has_line(set.out, "eeprom_value: 1234"));
}

TEST_CASE("set address with --config --sensor writes the new address into the file, only there") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223"});
  const std::string path = (sim.dir().path() / "plant.toml").string();
  const std::string before = "# plant\n[[bus]]\nname = \"line1\"\nport = \"" + sim.tty() +
                             "\"   # the RS485 adapter\n\n[[sensor]]\nname = \"boom\"\nbus = \"line1\"\n"
                             "model = \"h6\"\naddress = 223  # factory\nunit_id = 1\n";
  std::ofstream(path) << before;
  const auto set = run_command({"set", "--config", path, "--sensor", "boom", "address", "7"});
  INFO(set.out << set.err);
  CHECK(set.exit_code == 0);
  CHECK(has_line(set.out, "updated " + path + ": sensor boom address 223 -> 7"));
  std::ifstream in(path);
  const std::string after((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string expected = before;
  expected.replace(expected.find("address = 223"), 13, "address = 7");
  CHECK(after == expected);
  CHECK(run_command({"info", "--config", path, "--sensor", "boom"}).exit_code == 0);
}
