// `tiltgate raw` against `tiltgate sim FAMILY` on a pseudo-terminal: the exact bytes each way
// with the checksum's verdict and the reply decoded, a NAK or an exception with its meaning
// (exit 1), a silent address (exit 1) and bad data (exit 2).
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

// `tiltgate COMMAND --port TTY --protocol rieker ARGS...`
CommandResult rieker(const std::string& command, const SimulatorProcess& sim,
                     std::vector<std::string> args) {
  std::vector<std::string> all{command, "--port", sim.tty(), "--protocol", "rieker"};
  all.insert(all.end(), args.begin(), args.end());
  return run_command(all);
}

}  // namespace

TEST_CASE("raw sends a Rieker Get Serial and shows both frames, the CRC verdict and the serial") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223,h4360:101"});
  const auto raw = rieker("raw", sim, {"--address", "223", "--function", "37"});
  INFO(raw.out << raw.err);
  CHECK(raw.exit_code == 0);
  CHECK(has_line(raw.out, "sent:     00 DF 00 00 00 25 00 FF 09"));
  CHECK(has_line(raw.out, "received: 00 00 00 DF 00 25 0A 39 36 30 30 32 32 33 20 20 20 52 C5  (CRC ok)"));
  CHECK(has_line(raw.out, "serial:   9600223"));

  // A single-axis sensor asked for both axes refuses with NAK 2.
  const auto nak = rieker("raw", sim, {"--address", "101", "--function", "5", "--data", "04"});
  INFO(nak.out << nak.err);
  CHECK(nak.exit_code == 1);
  CHECK(has_line(nak.out, "reply:    NAK 2 (function not valid for this sensor or mode)"));

  const auto silent = rieker("raw", sim, {"--address", "7", "--function", "37"});
  CHECK(silent.exit_code == 1);
  CHECK(has_line(silent.out, "received: nothing"));
  CHECK(has(silent.err, "no reply from address 7"));

  const auto bad = rieker("raw", sim, {"--address", "223", "--function", "37", "--data", "0g"});
  CHECK(bad.exit_code == 2);
  CHECK(has(bad.err, "--data: \"0g\" is not hex bytes"));
}

TEST_CASE("raw on a Modbus RTU bus shows the registers read, and an exception with its meaning") {
  SimulatorProcess sim({"modbus-rtu", "--sensors", "modbus-rtu:1"});
  const std::string profile = std::string(TILTGATE_SOURCE_DIR) + "/examples/devices/rtu-inclinometer.toml";
  const std::vector<std::string> bus{"raw", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                     "--device", profile, "--address", "1", "--function", "3"};
  auto args = bus;
  args.insert(args.end(), {"--data", "00 00 00 02"});
  const auto read = run_command(args);
  INFO(read.out << read.err);
  CHECK(read.exit_code == 0);
  CHECK(has_line(read.out, "sent:     01 03 00 00 00 02 C4 0B"));
  CHECK(has(read.out, "(CRC ok)"));
  CHECK(has(read.out, "registers: "));
  args = bus;
  args.insert(args.end(), {"--data", "FF 00 00 02"});
  const auto refused = run_command(args);
  CHECK(refused.exit_code == 1);
  CHECK(has_line(refused.out, "reply:    exception 0x02 (illegal data address)"));
}

TEST_CASE("raw on a Modbus RTU line sends its PDU without a device profile") {
  SimulatorProcess sim({"modbus-rtu", "--sensors", "modbus-rtu:1"});
  const auto read = run_command({"raw", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                 "--address", "1", "--function", "3", "--data", "00 03 00 02"});
  INFO(read.out << read.err);
  CHECK(read.exit_code == 0);
  CHECK(has_line(read.out, "sent:     01 03 00 03 00 02 34 0B"));
  CHECK(has(read.out, "(CRC ok)"));
  CHECK(has_line(read.out, "registers: 102 360"));  // the preset's firmware and model
  const auto server_id = run_command({"raw", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                      "--address", "1", "--function", "17"});
  INFO(server_id.out << server_id.err);
  CHECK(server_id.exit_code == 0);
  CHECK(has(server_id.out, "reply:    function 0x11, PDU 11 1B 2A FF"));
}

TEST_CASE("raw on a Dyna's 9-bit bus sends the address byte, the command character and CR LF") {
  SimulatorProcess sim({"spectron", "--sensors", "dyna:1"});
  const auto raw = run_command({"raw", "--port", sim.tty(), "--protocol", "spectron-9bit", "--baud",
                                "28800", "--address", "1", "--function", "65"});
  INFO(raw.out << raw.err);
  CHECK(raw.exit_code == 0);
  CHECK(has_line(raw.out, "sent:     01 41 0D 0A  (the first byte with the 9th bit set)"));
  CHECK(has(raw.out, "(CR LF, no checksum)"));
  CHECK(has(raw.out, "reply:    \""));
}
