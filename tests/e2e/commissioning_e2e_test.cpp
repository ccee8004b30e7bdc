// `tiltgate info` and `tiltgate watch` against `tiltgate sim FAMILY` on a pseudo-terminal: the
// values the simulated sensors hold, a silent address, a wrong baud, a missing or busy tty and
// bad options, each with its exit code.
#include <doctest/doctest.h>

#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <sys/file.h>
#include <thread>
#include <unistd.h>

#include "e2e/support/front_end.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/output_checks.h"
#include "e2e/support/simulator_process.h"

using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

const std::string kRtuProfile = std::string(TILTGATE_SOURCE_DIR) + "/examples/devices/rtu-inclinometer.toml";

std::vector<std::string> words(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

// The watch rows (plain lines) for one address, split into their columns.
std::vector<std::vector<std::string>> rows_for(const std::string& out, const std::string& address) {
  std::vector<std::vector<std::string>> rows;
  for (const std::string& line : lines(out)) {
    auto w = words(line);
    if (!w.empty() && w[0] == address) rows.push_back(std::move(w));
  }
  return rows;
}

// "angle x:    1.234 deg" -> 1.234
double info_value(const std::string& out, const std::string& label) {
  for (const std::string& line : lines(out)) {
    if (line.rfind(label + ":", 0) == 0) return std::stod(line.substr(label.size() + 1));
  }
  FAIL("no line " << label << " in:\n" << out);
  return 0;
}

}  // namespace

TEST_CASE("info shows a Rieker sensor's identity, lock level and the simulator's angles") {
  // The simulator's sensors: angle x = 1 + index (+-0.25 sway), y = -x; serial 96 + address.
  SimulatorProcess sim({"rieker", "--sensors", "h6:223,h6:224,h4360:101", "--baud", "125000"});
  const auto info = run_command({"info", "--port", sim.tty(), "--protocol", "rieker",
                                 "--address", "224"});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 0);
  CHECK(has_line(info.out, "address:    224"));
  CHECK(has_line(info.out, "model:      h6"));
  CHECK(has_line(info.out, "serial:     9600224"));
  CHECK(has_line(info.out, "lock level: 0"));
  CHECK(info_value(info.out, "angle x") == doctest::Approx(2.0).epsilon(0.15));
  CHECK(info_value(info.out, "angle y") == doctest::Approx(-2.0).epsilon(0.15));
  CHECK(info_value(info.out, "tilt") > 2.0);

  // A single-axis model: no Y angle, the tilt is the X angle's magnitude.
  const auto mast = run_command({"info", "--port", sim.tty(), "--protocol", "rieker", "--model",
                                 "h4360", "--address", "101"});
  INFO(mast.out << mast.err);
  CHECK(mast.exit_code == 0);
  CHECK(has_line(mast.out, "angle y:    -"));
  CHECK(info_value(mast.out, "tilt") == doctest::Approx(info_value(mast.out, "angle x")));
}

TEST_CASE("info on an address nothing answers exits 1 with no reply and a hint") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223,h6:224", "--baud", "125000"});
  const auto info = run_command({"info", "--port", sim.tty(), "--address", "223,7"});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 1);
  CHECK(has_line(info.out, "serial:     9600223"));  // the one that answered is still shown
  CHECK(info.err.find("no reply from address 7 on " + sim.tty() + " at 125000 baud") !=
        std::string::npos);
  CHECK(info.err.find("hint:") != std::string::npos);
}

TEST_CASE("info at a baud the sensors are not set to gets no reply: exit 1 with the hint") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223", "--baud", "125000"});
  const auto info = run_command({"info", "--port", sim.tty(), "--baud", "9600", "--address", "223"});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 1);
  CHECK(info.err.find("no reply from address 223 on " + sim.tty() + " at 9600 baud") !=
        std::string::npos);
  CHECK(info.err.find("check the baud rate") != std::string::npos);
}

TEST_CASE("info on a missing tty, or one another command holds, exits 1 with the reason") {
  if (skipped_through_gateway("the command opens no tty there: the gateway holds it")) return;
  TempDir dir;
  const std::string missing = (dir.path() / "ttyUSB9").string();
  const auto gone = run_command({"info", "--port", missing, "--address", "223"});
  CHECK(gone.exit_code == 1);
  CHECK(gone.err.find("cannot open " + missing + ": No such file or directory") !=
        std::string::npos);

  SimulatorProcess sim({"rieker", "--sensors", "h6:223"});
  const int fd = ::open(sim.tty().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  REQUIRE(fd >= 0);
  REQUIRE(::flock(fd, LOCK_EX | LOCK_NB) == 0);
  const auto busy = run_command({"info", "--port", sim.tty(), "--address", "223"});
  ::close(fd);
  CHECK(busy.exit_code == 1);
  CHECK(busy.err.find("is in use") != std::string::npos);
}

TEST_CASE("bad commissioning options exit 2 and name the option") {
  const auto baud = run_command({"info", "--port", "/dev/null", "--protocol", "rieker", "--baud",
                                 "9601", "--address", "1"});
  CHECK(baud.exit_code == 2);
  CHECK(baud.err.find("--baud: 9601 is not a rieker baud rate") != std::string::npos);
  const auto address = run_command({"watch", "--port", "/dev/null", "--address", "0"});
  CHECK(address.exit_code == 2);
  CHECK(address.err.find("--address: 0 is out of range") != std::string::npos);
  const auto not_a_number = run_command({"info", "--port", "/dev/null", "--address", "x"});
  CHECK(not_a_number.exit_code == 2);
  const auto no_bus = run_command({"watch", "--address", "1"});
  CHECK(no_bus.exit_code == 2);
  CHECK(no_bus.err.find("--port: required") != std::string::npos);
  const auto interval = run_command({"watch", "--port", "/dev/null", "--address", "1",
                                     "--interval", "0"});
  CHECK(interval.exit_code == 2);
  const auto help = run_command({"watch", "--help"});
  CHECK(help.exit_code == 0);
  CHECK(help.out.find("Examples:") != std::string::npos);
}

TEST_CASE("watch --count 2 prints a row per sensor per round with the simulator's values, and logs them") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223,h6:224", "--baud", "125000"});
  const std::string csv = (sim.dir().path() / "angles.csv").string();
  const auto watch = run_command({"watch", "--port", sim.tty(), "--address", "223,224,7",
                                  "--count", "2", "--interval", "50", "--log", csv});
  INFO(watch.out << watch.err);
  CHECK(watch.exit_code == 0);
  CHECK(words(lines(watch.out).at(0)).at(0) == "ADDRESS");
  CHECK(lines(watch.out).size() == 1 + 2 * 3);
  for (const auto& [address, serial, x] :
       {std::tuple{"223", "9600223", 1.0}, std::tuple{"224", "9600224", 2.0}}) {
    const auto rows = rows_for(watch.out, address);
    REQUIRE(rows.size() == 2);
    for (const auto& row : rows) {
      REQUIRE(row.size() == 8);
      CHECK(row[1] == serial);
      CHECK(std::stod(row[2]) == doctest::Approx(x).epsilon(0.3));
      CHECK(std::stod(row[3]) == doctest::Approx(-x).epsilon(0.3));
      CHECK(row[5] == "ok");
    }
  }
  const auto silent = rows_for(watch.out, "7");
  REQUIRE(silent.size() == 2);
  CHECK(silent[0][5] == "no-reply");
  CHECK(silent[0][2] == "-");

  // Every reading in the CSV; a second run appends without another header.
  const auto again = run_command({"watch", "--port", sim.tty(), "--address", "224", "--count",
                                  "1", "--log", csv});
  CHECK(again.exit_code == 0);
  std::ifstream in(csv);
  std::stringstream text;
  text << in.rdbuf();
  const auto logged = lines(text.str());
  REQUIRE(logged.size() == 1 + 2 * 3 + 1);
  CHECK(logged[0] == "time,address,serial,x_deg,y_deg,tilt_deg,status");
  CHECK(logged[1].find(",223,9600223,") == 24);
  CHECK(logged[3].find(",7,,,,,no-reply") == 24);
  CHECK(logged[7].find(",224,9600224,") == 24);
}

TEST_CASE("watch takes a Spectron bus and its sensors from a configuration") {
  SimulatorProcess sim({"spectron", "--protocol", "9bit", "--sensors", "dyna:1,dyna:2", "--baud",
                        "28800"});
  // The simulator's modules: serial 10000 + address, 1000 counts per index (+-50 sway).
  const auto config = sim.dir().write("plant.toml", R"(
[[bus]]
name = "dyna-line"
port = ")" + sim.tty() + R"("
protocol = "spectron-9bit"
baud = 28800

[[sensor]]
name = "jib"
bus = "dyna-line"
model = "dyna"
address = 1
unit_id = 1
counts_per_degree = 100
zero_counts = 0

[[sensor]]
name = "slew"
bus = "dyna-line"
model = "dyna"
address = 2
unit_id = 2
counts_per_degree = 100
zero_counts = 0
)");
  const auto watch = run_command({"watch", "--config", config.string(), "--bus", "dyna-line",
                                  "--count", "2", "--interval", "50"});
  INFO(watch.out << watch.err);
  CHECK(watch.exit_code == 0);
  const auto first = rows_for(watch.out, "1");
  const auto second = rows_for(watch.out, "2");
  REQUIRE(first.size() == 2);
  REQUIRE(second.size() == 2);
  CHECK(first[1][1] == "10001");
  CHECK(std::stod(first[1][2]) == doctest::Approx(10.0).epsilon(0.06));
  CHECK(first[1][3] == "-");
  CHECK(second[1][1] == "10002");
  CHECK(std::stod(second[1][2]) == doctest::Approx(20.0).epsilon(0.03));

  const auto info = run_command({"info", "--config", config.string(), "--sensor", "slew"});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 0);
  CHECK(has_line(info.out, "serial:     10002"));
  CHECK(has_line(info.out, "lock level: -"));
}

TEST_CASE("info and watch read Modbus RTU devices through their device profile") {
  // The simulator's slaves: angle x = 1 + index, y = -x.
  SimulatorProcess sim({"modbus-rtu", "--sensors", "modbus-rtu:1,modbus-rtu:7", "--baud", "19200"});
  const auto info = run_command({"info", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                 "--device", kRtuProfile, "--address", "7"});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 0);
  CHECK(info_value(info.out, "angle x") == doctest::Approx(2.0));
  CHECK(info_value(info.out, "angle y") == doctest::Approx(-2.0));

  const auto watch = run_command({"watch", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                  "--device", kRtuProfile, "--address", "1,7,9", "--count", "2",
                                  "--interval", "50"});
  INFO(watch.out << watch.err);
  CHECK(watch.exit_code == 0);
  const auto one = rows_for(watch.out, "1");
  REQUIRE(one.size() == 2);
  CHECK(one[0][2] == "1.000");
  CHECK(one[0][3] == "-1.000");
  const auto nine = rows_for(watch.out, "9");
  REQUIRE(nine.size() == 2);
  CHECK(nine[1][5] == "no-reply");

  const auto silent = run_command({"info", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                   "--device", kRtuProfile, "--address", "9"});
  CHECK(silent.exit_code == 1);
}

TEST_CASE("info shows the serial, firmware and model a Modbus RTU profile's [identity] names") {
  SimulatorProcess sim({"modbus-rtu", "--sensors", "modbus-rtu:7"});
  const auto info = run_command({"info", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                 "--device", kRtuProfile, "--address", "7"});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 0);
  CHECK(has_line(info.out, "serial:     20240917"));
  CHECK(has_line(info.out, "firmware:   1.02"));
  // The profile's model_name (the device reports 360).
  CHECK(has_line(info.out, "model:      RTU inclinometer (modbus-rtu)"));
}

TEST_CASE("info on a Modbus RTU device without --device shows what it says of itself") {
  SimulatorProcess sim({"modbus-rtu", "--sensors", "modbus-rtu:7"});
  const auto info = run_command({"info", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                 "--address", "7"});
  INFO(info.out << info.err);
  CHECK(info.exit_code == 0);
  CHECK(has_line(info.out, "address:    7"));
  CHECK(has_line(info.out, "vendor:     tiltgate"));
  CHECK(has_line(info.out, "product:    TG-RTU-INC"));
  CHECK(has_line(info.out, "revision:   1.02"));
  CHECK(has_line(info.out, "model:      360"));
  CHECK(has_line(info.out, "server id:  0x2A, run indicator ON, tiltgate RTU inclinometer"));
  CHECK_FALSE(has(info.err, "required key"));

  const auto silent = run_command({"info", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                   "--address", "9"});
  INFO(silent.out << silent.err);
  CHECK(silent.exit_code == 1);
  CHECK(has(silent.err, "no reply from address 9"));

  const auto out_of_range = run_command({"info", "--port", sim.tty(), "--protocol",
                                         "modbus-rtu", "--address", "248"});
  CHECK(out_of_range.exit_code == 2);
  CHECK(has(out_of_range.err, "--address: 248 is out of range for a modbus-rtu bus"));
  // watch still needs the profile: it reads the values it describes.
  const auto watch = run_command({"watch", "--port", sim.tty(), "--protocol", "modbus-rtu",
                                  "--address", "7", "--count", "1"});
  CHECK(watch.exit_code == 2);
  CHECK(has(watch.err, "--device: required key is missing"));
}

TEST_CASE("watch runs until SIGTERM and then exits 0") {
  SimulatorProcess sim({"rieker", "--sensors", "h6:223"});
  TempDir dir;
  CommandProcess watch({"watch", "--port", sim.tty(), "--address", "223", "--interval", "50"},
                       dir.path());
  const auto deadline = std::chrono::steady_clock::now() + 15s;
  while (rows_for(watch.output(), "223").size() < 2 && watch.running() &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(20ms);
  REQUIRE_MESSAGE(rows_for(watch.output(), "223").size() >= 2, watch.log());
  CHECK(watch.terminate() == 0);
}
