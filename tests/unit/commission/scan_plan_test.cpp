// `tiltgate scan`'s plan and output: the addresses and rates probed, the default probe
// time-out, the rows, summary and progress bar, and the configuration --config-out writes.
#include <doctest/doctest.h>

#include <algorithm>

#include "config/config_loader.h"
#include "commission/scan_plan.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

const ProtocolDescriptor& protocol_named(std::string_view name) {
  const ProtocolEntry entry = find_protocol(registered_families(), name);
  REQUIRE(entry.protocol != nullptr);
  return *entry.protocol;
}

bool contains(const std::vector<std::uint32_t>& list, std::uint32_t value) {
  return std::find(list.begin(), list.end(), value) != list.end();
}

// A protocol whose factory address lies outside its usual scan range.
constexpr std::uint32_t kFarFactory[] = {5, 900};
constexpr std::int64_t kTwoBauds[] = {9600, 19200};
ProtocolDescriptor far_factory_protocol() {
  ProtocolDescriptor p;
  p.name = "test";
  p.bauds = kTwoBauds;
  p.addresses = {1, 1000};
  p.scan.first = 1;
  p.scan.last = 10;
  p.scan.factory_addresses = kFarFactory;
  return p;
}

FoundSensor found_at(std::uint32_t address, std::uint32_t baud, std::string model = "",
                     bool collision = false) {
  FoundSensor s;
  s.address = address;
  s.baud = baud;
  s.model = std::move(model);
  s.collision = collision;
  return s;
}

BusConfig scanned_bus() {
  BusConfig bus;
  bus.name = "command-line";
  bus.port = "/dev/ttyUSB0";
  bus.protocol = "rieker";
  bus.baud = 125000;
  return bus;
}

}  // namespace

TEST_CASE("a Rieker scan without a range probes 1..255 once each, the factory address among them") {
  auto addresses = scan_addresses(protocol_named("rieker"), std::nullopt, std::nullopt);
  REQUIRE(addresses.has_value());
  CHECK(addresses->size() == 255);
  CHECK(addresses->front() == 1);
  CHECK(addresses->back() == 255);
  CHECK(contains(*addresses, 223));
}

TEST_CASE("factory addresses outside the usual range are probed too, once, in order") {
  auto addresses = scan_addresses(far_factory_protocol(), std::nullopt, std::nullopt);
  REQUIRE(addresses.has_value());
  CHECK(*addresses == std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 900});
}

TEST_CASE("a range given probes exactly that range, and a missing bound is the usual one") {
  auto range = scan_addresses(far_factory_protocol(), 3, 4);
  REQUIRE(range.has_value());
  CHECK(*range == std::vector<std::uint32_t>{3, 4});
  auto from_only = scan_addresses(far_factory_protocol(), 8, std::nullopt);
  REQUIRE(from_only.has_value());
  CHECK(*from_only == std::vector<std::uint32_t>{8, 9, 10});
  auto long_scan = scan_addresses(protocol_named("rieker"), 1, 65000);
  REQUIRE(long_scan.has_value());
  CHECK(long_scan->size() == 65000);
}

TEST_CASE("a range past the protocol's addresses or backwards is refused, naming the option") {
  auto past = scan_addresses(protocol_named("rieker"), 1, 65001);
  REQUIRE_FALSE(past.has_value());
  CHECK(past.error().find("--to: 65001 is outside") == 0);
  CHECK(past.error().find("1..65000") != std::string::npos);
  auto below = scan_addresses(protocol_named("modbus-rtu"), 0, 5);
  REQUIRE_FALSE(below.has_value());
  CHECK(below.error().find("--from: 0 is outside") == 0);
  auto backwards = scan_addresses(protocol_named("rieker"), 10, 5);
  REQUIRE_FALSE(backwards.has_value());
  CHECK(backwards.error().find("--from: 10 is past --to 5") == 0);
  auto past_default_end = scan_addresses(protocol_named("rieker"), 300, std::nullopt);
  REQUIRE_FALSE(past_default_end.has_value());
  CHECK(past_default_end.error().find("give --to") != std::string::npos);
}

TEST_CASE("--baud auto tries the bus's rate first, then every other rate of the protocol once") {
  const ProtocolDescriptor& rieker = protocol_named("rieker");
  CHECK(scan_bauds(rieker, 38400, false) == std::vector<std::uint32_t>{38400});
  const auto bauds = scan_bauds(rieker, 38400, true);
  CHECK(bauds.size() == rieker.bauds.size());
  CHECK(bauds.front() == 38400);
  for (const std::int64_t b : rieker.bauds) CHECK(contains(bauds, std::uint32_t(b)));
}

TEST_CASE("--baud auto is refused over raw TCP and where the devices speak TCP, with the reason") {
  const ProtocolDescriptor& rieker = protocol_named("rieker");
  CHECK_FALSE(auto_baud_refusal(rieker, "/dev/ttyUSB0"));
  // RFC 2217 sets the far port's rate for each try, as termios does on a tty.
  CHECK_FALSE(auto_baud_refusal(rieker, "rfc2217://192.168.1.20:4001"));
  CHECK(auto_baud_refusal(rieker, "tcp://192.168.1.20:4001") ==
        "--baud auto: not over tcp:// (raw TCP cannot change the device server's rate: it is "
        "the server's own setting); use rfc2217://192.168.1.20:4001 if the server offers RFC "
        "2217 (the rate is then set for each try), or set each rate on the server and scan "
        "with --baud RATE");
  ProtocolDescriptor tcp_devices = rieker;
  tcp_devices.name = "tcp-devices";
  tcp_devices.title = "Modbus TCP";
  tcp_devices.devices_speak_tcp = true;
  CHECK(auto_baud_refusal(tcp_devices, "tcp://10.0.0.7:502") ==
        "--baud auto: a tcp-devices bus has no serial line and no rate: the devices speak "
        "Modbus TCP");
}

TEST_CASE("the default probe time-out is the protocol's reply time plus the adapter allowance") {
  for (const char* name : {"rieker", "spectron-9bit", "spectron-modbus", "modbus-rtu"}) {
    CAPTURE(name);
    const ProtocolDescriptor& p = protocol_named(name);
    REQUIRE(bool(p.scan.probe));
    REQUIRE(bool(p.scan.probe_time));
    const auto slow = default_probe_timeout(p, std::uint32_t(p.bauds.front()));
    const auto fast = default_probe_timeout(p, std::uint32_t(p.bauds.back()));
    CHECK(fast > kProbeAllowance);
    CHECK(slow > fast);
  }
  // 255 silent addresses at the Rieker factory rate, each costing the time-out and as much
  // quiet after it: seconds, not minutes.
  const auto rieker = default_probe_timeout(protocol_named("rieker"), 125000);
  CHECK(rieker <= 20ms);
  CHECK(255 * 2 * rieker < 15s);
}

TEST_CASE("a scan row shows the identity, and a collision says so") {
  FoundSensor sensor = found_at(223, 125000, "h6");
  sensor.serial = "962285";
  sensor.firmware = "Rev A.8";
  sensor.lock_level = 0;
  const std::string row = scan_row(sensor);
  CHECK(row.find("223") == 0);
  for (const char* field : {"125000", "h6", "962285", "Rev A.8", "ok"})
    CHECK(row.find(field) != std::string::npos);
  FoundSensor collision = found_at(5, 125000, "", true);
  collision.detail = "bad CRC";
  CHECK(scan_row(collision).find("probable collision") != std::string::npos);
  CHECK(scan_row(collision).find("bad CRC") != std::string::npos);
}

TEST_CASE("the summary counts sensors and collisions apart, with their addresses and rates") {
  const std::vector<FoundSensor> found{found_at(5, 38400, "", true), found_at(101, 38400),
                                       found_at(223, 38400)};
  const std::string summary = scan_summary(found, 256, 4100ms);
  CHECK(summary.find("2 sensor(s) found at 38400 baud: 101, 223") == 0);
  CHECK(summary.find("1 probable collision(s) (address 5)") != std::string::npos);
  CHECK(summary.find("256 probe(s) in 4.1 s") != std::string::npos);
  CHECK(scan_summary({}, 10, 100ms).find("0 sensor(s) found;") == 0);
}

TEST_CASE("the progress line shows the count and the addresses found, within the width") {
  std::vector<FoundSensor> found{found_at(12, 9600), found_at(40, 9600)};
  const std::string line = progress_line(128, 256, 9600, found);
  CHECK(line.find("[##########..........] 128/256 at 9600 baud") == 0);
  CHECK(line.find("found: 12 40") != std::string::npos);
  for (std::uint32_t a = 100; a < 200; ++a) found.push_back(found_at(a, 9600));
  CHECK(progress_line(256, 256, 9600, found, 60).size() == 60);
}

TEST_CASE("--config-out's configuration loads, one sensor per sensor found at the bus's rate") {
  const std::vector<FoundSensor> found{found_at(5, 125000, "", true),
                                       found_at(101, 125000, "h4360"), found_at(223, 125000, "h6"),
                                       found_at(77, 9600, "h6")};
  const std::string text = scan_config_text(scanned_bus(), found, {});
  INFO(text);
  auto config = load_config_string(text, "scan", registered_families());
  REQUIRE(config.has_value());
  REQUIRE(config->buses.size() == 1);
  CHECK(config->buses[0].baud == 125000);
  CHECK(config->buses[0].port == "/dev/ttyUSB0");
  REQUIRE(config->sensors.size() == 2);
  CHECK(config->sensors[0].name == "sensor_101");
  CHECK(config->sensors[0].model == "h4360");
  CHECK(config->sensors[0].unit_id == 1);
  CHECK(config->sensors[1].name == "sensor_223");
  CHECK(config->sensors[1].address == 223);
  CHECK(config->sensors[1].unit_id == 2);
  // The collision and the sensor at another rate are told, not configured.
  CHECK(text.find("# Address 5: garbled replies") != std::string::npos);
  CHECK(text.find("# Address 77 answered at 9600 baud") != std::string::npos);
}

TEST_CASE("--config-out writes each sensor's serial as its serial key, so a swapped one is not served") {
  FoundSensor sensor = found_at(223, 125000, "h6");
  sensor.serial = "9600223";
  sensor.firmware = "Rev A.8";
  const std::string text =
      scan_config_text(scanned_bus(), {sensor, found_at(101, 125000, "h4360")}, {});
  INFO(text);
  CHECK(text.find("serial = \"9600223\"    # firmware Rev A.8\n") != std::string::npos);
  auto config = load_config_string(text, "scan", registered_families());
  REQUIRE(config.has_value());
  REQUIRE(config->sensors.size() == 2);
  CHECK(config->sensors[0].serial == "9600223");
  CHECK(config->sensors[1].serial.empty());  // 101 reported none: any device is served
}

TEST_CASE("--config-out writes the family's required keys into every sensor") {
  BusConfig bus = scanned_bus();
  bus.protocol = "modbus-rtu";
  bus.baud = 19200;
  bus.framing = Framing::eight_none_two;
  const std::vector<FoundSensor> found{found_at(1, 19200, "modbus-rtu"),
                                       found_at(2, 19200, "modbus-rtu")};
  const std::string text = scan_config_text(bus, found, {{"device", "/etc/tiltgate/dev.toml"}});
  CHECK(text.find("parity = \"none\"\nstop_bits = 2\n") != std::string::npos);
  std::size_t devices = 0;
  for (std::size_t at = text.find("device = \"/etc/tiltgate/dev.toml\""); at != std::string::npos;
       at = text.find("device = ", at + 1))
    ++devices;
  CHECK(devices == 2);
}

TEST_CASE("the sensors a scan's configuration holds, each with its own table") {
  FoundSensor first = found_at(5, 125000, "h6");
  first.serial = "A123";
  first.firmware = "2.1";
  const std::vector<FoundSensor> found{first, found_at(7, 125000, "", true),
                                       found_at(9, 125000, "")};
  const std::vector<SensorTable> tables = sensor_tables(scanned_bus(), found, {});
  REQUIRE(tables.size() == 2);
  CHECK(tables[0].address == 5);
  CHECK(tables[0].model == "h6");
  CHECK(tables[0].serial == "A123");
  CHECK(tables[0].firmware == "2.1");
  CHECK(tables[0].text.starts_with("[[sensor]]\nname = \"sensor_5\""));
  CHECK(tables[0].text.ends_with("# firmware 2.1\n"));
  CHECK(tables[1].address == 9);
  CHECK(tables[1].serial.empty());
  // Each table is the configuration's own, word for word.
  const std::string text = scan_config_text(scanned_bus(), found, {});
  for (const SensorTable& table : tables) CHECK(text.find(table.text) != std::string::npos);
}

TEST_CASE("--baud auto: a serial found again at later rates is one sensor, kept where first found") {
  auto with_serial = [](std::uint32_t address, std::uint32_t baud, std::string serial) {
    FoundSensor s = found_at(address, baud, "h6");
    s.serial = std::move(serial);
    return s;
  };
  std::vector<FoundSensor> found{with_serial(12, 125000, "9600012"), found_at(5, 125000, "", true),
                                 with_serial(12, 9600, "9600012"), with_serial(13, 9600, "9600013"),
                                 found_at(5, 9600, "", true), with_serial(14, 9600, ""),
                                 with_serial(12, 19200, "9600012"), with_serial(15, 19200, "")};
  const std::vector<RepeatedSensor> repeated = drop_repeated_sensors(found);
  // Collisions and sensors without a serial read are all kept: nothing says they are one.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> kept;
  for (const FoundSensor& s : found) kept.emplace_back(s.address, s.baud);
  CHECK(kept == std::vector<std::pair<std::uint32_t, std::uint32_t>>{
                    {12, 125000}, {5, 125000}, {13, 9600}, {5, 9600}, {14, 9600}, {15, 19200}});
  REQUIRE(repeated.size() == 1);
  CHECK(repeated[0].address == 12);
  CHECK(repeated[0].kept_baud == 125000);
  CHECK(repeated[0].other_bauds == std::vector<std::uint32_t>{9600, 19200});
  CHECK(repeated_note(repeated[0]) ==
        "note: serial 9600012 (address 12) answered at 9600, 19200 baud too: one sensor, listed "
        "once, at 125000 baud");
}

TEST_CASE("two devices at one rate that report one serial are two sensors, both listed") {
  auto with_serial = [](std::uint32_t address, std::uint32_t baud, std::string serial) {
    FoundSensor s = found_at(address, baud, "rtu-inclinometer");
    s.serial = std::move(serial);
    return s;
  };
  std::vector<FoundSensor> found{with_serial(5, 19200, "20240917"),
                                 with_serial(9, 19200, "20240917")};
  const std::vector<RepeatedSensor> repeated = drop_repeated_sensors(found);
  CHECK(repeated.empty());
  REQUIRE(found.size() == 2);
  CHECK(found[0].address == 5);
  CHECK(found[1].address == 9);
}
