// `tiltgate scan` against `tiltgate sim FAMILY` on a pseudo-terminal: several sensors, two at
// one address, a silent bus, a wrong baud and --baud auto, each family's probe, and bad options,
// each with its exit code.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "e2e/support/front_end.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/simulator_process.h"

using namespace tiltgate::test;

namespace {

const std::string kRtuProfile =
    std::string(TILTGATE_SOURCE_DIR) + "/examples/devices/rtu-inclinometer.toml";

// The scan row for `address`, split into its columns (the status may hold blanks: it is last).
std::vector<std::string> row_for(const std::string& out, const std::string& address) {
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream in(line);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    if (!words.empty() && words[0] == address) return words;
  }
  return {};
}

bool mentions(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("scan finds every sensor on a Rieker bus, with its model, serial, firmware and lock") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223,h6:224,h4360:101", "--baud", "125000"});
  const auto scan = run_command({"scan", "--port", sim.tty()});
  INFO(scan.out << scan.err);
  CHECK(scan.exit_code == 0);
  CHECK(row_for(scan.out, "223") ==
        std::vector<std::string>{"223", "125000", "h6", "9600223", "Rev", "A.8", "0", "ok"});
  CHECK(row_for(scan.out, "224").at(2) == "h6");
  // The single-axis sensor refuses the dual-axis reading: its model is found by trying.
  CHECK(row_for(scan.out, "101").at(2) == "h4360");
  CHECK(mentions(scan.out, "3 sensor(s) found at 125000 baud: 101, 223, 224; 255 probe(s)"));
}

TEST_CASE("scan reports two sensors at one address as a probable collision, and goes on") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:5,h6:5,h6:7", "--shared-addresses"});
  const auto scan = run_command({"scan", "--port", sim.tty(), "--from", "1", "--to", "10"});
  INFO(scan.out << scan.err);
  CHECK(scan.exit_code == 0);
  const auto collision = row_for(scan.out, "5");
  REQUIRE(collision.size() > 6);
  CHECK(collision[6] == "probable");
  CHECK(mentions(scan.out, "bad CRC"));
  CHECK(row_for(scan.out, "7").back() == "ok");
  CHECK(mentions(scan.out, "1 sensor(s) found at 125000 baud: 7; 1 probable collision(s) (address 5)"));
}

TEST_CASE("scan of a bus where nothing answers exits 1 with what to check") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:300"});
  const auto scan = run_command({"scan", "--port", sim.tty(), "--to", "20"});
  INFO(scan.out << scan.err);
  CHECK(scan.exit_code == 1);
  CHECK(mentions(scan.out, "0 sensor(s) found; 20 probe(s)"));
  CHECK(mentions(scan.err, "no sensor answered on " + sim.tty()));
  CHECK(mentions(scan.err, "--baud auto"));
}

TEST_CASE("scan at the wrong baud finds nothing, but --baud auto finds the sensor at its rate") {
  if (skipped_through_gateway("--baud auto is refused: the gateway's bus keeps its rate")) return;
  SimulatorProcess sim({"rieker", "--sensors", "h6:12", "--baud", "38400"});
  const auto wrong = run_command({"scan", "--port", sim.tty(), "--from", "10", "--to", "14"});
  INFO(wrong.out << wrong.err);
  CHECK(wrong.exit_code == 1);

  const auto found = run_command(
      {"scan", "--port", sim.tty(), "--baud", "auto", "--from", "10", "--to", "14"});
  INFO(found.out << found.err);
  CHECK(found.exit_code == 0);
  const auto row = row_for(found.out, "12");
  REQUIRE(row.size() > 3);
  CHECK(row[1] == "38400");
  CHECK(row[3] == "9600012");
  CHECK(mentions(found.out, "1 sensor(s) found at 38400 baud: 12; 40 probe(s)"));  // 8 rates
}

TEST_CASE("scan --baud auto lists a sensor that answers at every rate once, and says so") {
  if (skipped_through_gateway("--baud auto is refused: the gateway's bus keeps its rate")) return;
  // No --baud: the simulated sensor answers at any rate, as one that detects the rate does.
  SimulatorProcess sim({"rieker", "--sensors", "h6:12"});
  const auto found = run_command(
      {"scan", "--port", sim.tty(), "--baud", "auto", "--from", "10", "--to", "14"});
  INFO(found.out << found.err);
  CHECK(found.exit_code == 0);
  std::size_t rows = 0;
  std::istringstream lines(found.out);
  for (std::string line; std::getline(lines, line);) rows += line.rfind("12 ", 0) == 0;
  CHECK(rows == 1);
  CHECK(row_for(found.out, "12").at(1) == "125000");  // where it was found first
  CHECK(mentions(found.out, "note: serial 9600012 (address 12) answered at "));
  CHECK(mentions(found.out, "baud too: one sensor, listed once, at 125000 baud"));
  CHECK(mentions(found.out, "1 sensor(s) found at 125000 baud: 12;"));
}

TEST_CASE("scan of a protocol without a default rate and no --baud names only --baud") {
  SimulatorProcess sim({"spectron", "--protocol", "modbus", "--sensors", "dyna:1"});
  const auto scan = run_command({"scan", "--port", sim.tty(), "--protocol", "spectron-modbus"});
  INFO(scan.out << scan.err);
  CHECK(scan.exit_code == 2);
  CHECK(mentions(scan.err, "--baud"));
  CHECK_FALSE(mentions(scan.err, "[[sensor]]"));
}

TEST_CASE("scan --broadcast asks the one sensor on the bus for its address, with a warning") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:4242"});
  const auto scan = run_command({"scan", "--port", sim.tty(), "--broadcast"});
  INFO(scan.out << scan.err);
  CHECK(scan.exit_code == 0);
  CHECK(row_for(scan.out, "4242").at(2) == "h6");
  CHECK(mentions(scan.err, "works only with one sensor on the bus"));
}

TEST_CASE("scan finds Dyna modules in either protocol, the 9-bit factory address 0 included") {
  SimulatorProcess ascii({"spectron", "--protocol", "modbus", "--sensors", "dyna:1,dyna:4",
                          "--baud", "28800"});
  const auto modbus = run_command({"scan", "--port", ascii.tty(), "--protocol",
                                   "spectron-modbus", "--baud", "28800", "--to", "6"});
  INFO(modbus.out << modbus.err);
  CHECK(modbus.exit_code == 0);
  CHECK(row_for(modbus.out, "1").at(2) == "dyna");
  CHECK(row_for(modbus.out, "4").at(3) == "10004");
  CHECK(mentions(modbus.out, "2 sensor(s) found at 28800 baud: 1, 4"));

  SimulatorProcess nine_bit({"spectron", "--protocol", "9bit", "--sensors", "dyna:0,dyna:2,dyna:2",
                             "--shared-addresses"});
  const auto scan = run_command({"scan", "--port", nine_bit.tty(), "--protocol", "spectron-9bit",
                                 "--baud", "9600", "--to", "3"});
  INFO(scan.out << scan.err);
  CHECK(scan.exit_code == 0);
  CHECK(row_for(scan.out, "0").at(2) == "dyna");
  CHECK(mentions(scan.out, "probable collision(s) (address 2)"));
}

TEST_CASE("scan finds Modbus RTU devices by FC 17 without a profile, by its first block with one") {
  SimulatorProcess sim({"modbus-rtu", "--sensors", "modbus-rtu:1,modbus-rtu:3,modbus-rtu:3",
                        "--shared-addresses"});
  const auto bare = run_command({"scan", "--port", sim.tty(), "--protocol", "modbus-rtu", "--to", "4"});
  INFO(bare.out << bare.err);
  CHECK(bare.exit_code == 0);
  // The preset answers FC 17 (a device without it, found by its "illegal function", is the sim
  // test's, tests/sim/families/scan_probe_test.cpp).
  CHECK(row_for(bare.out, "1") == std::vector<std::string>{"1", "19200", "-", "-", "-", "-", "ok"});
  CHECK(mentions(bare.out, "1 sensor(s) found at 19200 baud: 1; 1 probable collision(s) (address 3)"));

  const auto profiled = run_command({"scan", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                     "--device", kRtuProfile, "--to", "4"});
  INFO(profiled.out << profiled.err);
  CHECK(profiled.exit_code == 0);
  CHECK(row_for(profiled.out, "1") ==
        std::vector<std::string>{"1", "19200", "modbus-rtu", "20240917", "1.02", "-", "ok"});

  // A configuration of devices without a profile would not pass `tiltgate check`.
  TempDir dir;
  const auto refused = run_command({"scan", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                    "--to", "4", "--config-out", (dir.path() / "x.toml").string()});
  CHECK(refused.exit_code == 2);
  CHECK(mentions(refused.err, "--config-out: modbus-rtu sensors need device"));
}

TEST_CASE("bad scan options exit 2 and name the option") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223"});
  TempDir dir;
  const std::string existing = dir.write("taken.toml", "# mine\n").string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"--from", "10", "--to", "5"}, "--from: 10 is past --to 5"},
      {{"--to", "65001"}, "--to: 65001 is outside the rieker protocol's addresses 1..65000"},
      {{"--config-out", existing}, "--config-out: " + existing + " exists (--force overwrites it)"},
      {{"--protocol", "spectron-9bit", "--baud", "9600", "--broadcast"},
       "--broadcast: the spectron-9bit protocol has no request every sensor answers"},
      {{"--baud", "fast"}, "--baud"},
  };
  for (const auto& refused : cases) {
    // Not a structured binding: INFO's lambda cannot capture one in C++20 (clang refuses).
    const auto& options = refused.first;
    const auto& message = refused.second;
    std::vector<std::string> args{"scan", "--port", sim.tty()};
    args.insert(args.end(), options.begin(), options.end());
    const auto scan = run_command(args);
    INFO(options.front() << ": " << scan.out << scan.err);
    CHECK(scan.exit_code == 2);
    CHECK(mentions(scan.err, message));
  }
  std::ifstream kept(existing);
  std::string first_line;
  std::getline(kept, first_line);
  CHECK(first_line == "# mine");
}
