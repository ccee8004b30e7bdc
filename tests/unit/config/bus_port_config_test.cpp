// [[bus]] port as a serial device server (tcp://, rfc2217://) or as devices that speak TCP
// themselves, and what each refuses: URLs checked at the key's line without connecting, one
// device server port per bus, no 9-bit framing and no kernel RS485 over a network, and no
// serial line keys where there is no serial line. The last with a protocol defined only here
// (ProtocolDescriptor::devices_speak_tcp), so it does not wait for the family that has one.
#include <doctest/doctest.h>

#include <array>
#include <string>
#include <string_view>

#include "config/config_loader.h"
#include "driver/family.h"
#include "mapping/common_block.h"
#include "mapping/register_map.h"
#include "unit/support/config_text.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// Lines 1..3 a Rieker bus on `port`, then `more`, then its sensor (6 lines).
std::string rieker_on(std::string_view port, std::string_view more = "") {
  return "[[bus]]\nname = \"line1\"\nport = \"" + std::string(port) + "\"\n" + std::string(more) +
         sensor_text("boom", "line1", 223, 1);
}

// A second Rieker bus, lines 1..3, on `port`.
std::string second_bus(std::string_view port) {
  return "[[bus]]\nname = \"line2\"\nport = \"" + std::string(port) + "\"\n";
}

// --- A protocol whose devices speak TCP themselves, and a serial one beside it. ---

constexpr std::array<std::int64_t, 1> kSerialBauds{9600};

const ProtocolDescriptor kProtocols[] = {
    {
        .name = "tcp-devices",
        .short_name = "tcp",
        .title = "Modbus TCP",
        .framing = Framing::eight_none_one,
        .bauds = {},
        .default_baud = std::nullopt,
        .addresses = {1, 247},
        .master_addresses = std::nullopt,
        .devices_speak_tcp = true,
    },
    {
        .name = "serial-devices",
        .short_name = "serial",
        .title = "Serial",
        .framing = Framing::eight_even_one,
        .bauds = kSerialBauds,
        .default_baud = 9600,
        .addresses = {1, 247},
        .master_addresses = std::nullopt,
    },
};

RegisterMap plain_map() { return RegisterMap(common_block(CommonBlockModel{})); }

const ModelDescriptor kModels[] = {{
    .name = "plain",
    .model_code = 9,
    .identity = {"Acme Sensors", "P", "P inclinometer"},
    .axes = 2,
    .default_map = plain_map,
    .sources = {},
    .settings = {},
}};

void read_no_keys(SensorKeyReader&, FamilyOptions&) {}
std::unique_ptr<SensorDriver> make_no_driver(const DriverSetup&) { return nullptr; }

const FamilyDescriptor kFamily{
    .name = "acme",
    .protocols = kProtocols,
    .models = kModels,
    .sensor_keys = {},
    .read_sensor_keys = read_no_keys,
    .make_driver = make_no_driver,
};
const FamilyDescriptor* const kList[] = {&kFamily};

// Lines 1..4 a tcp-devices bus on `port`, then `more`, then one sensor.
std::string tcp_devices_on(std::string_view port, std::string_view more = "") {
  return "[[bus]]\nname = \"plc\"\nport = \"" + std::string(port) +
         "\"\nprotocol = \"tcp-devices\"\n" + std::string(more) +
         "[[sensor]]\nname = \"s\"\nbus = \"plc\"\nmodel = \"plain\"\naddress = 1\nunit_id = 1\n";
}

ConfigErrors acme_errors(const std::string& text) {
  auto loaded = load_config_string(text, "acme.toml", kList);
  REQUIRE_FALSE(loaded.has_value());
  return loaded.error();
}

void expect_acme_error(const std::string& text, int line, std::string_view key,
                       std::string_view message) {
  CAPTURE(text);
  const ConfigErrors errors = acme_errors(text);
  INFO(joined(errors));
  REQUIRE(errors.size() == 1);
  CHECK(errors[0].line == line);
  CHECK(errors[0].key == key);
  CHECK(errors[0].message == message);
}

Config acme_loads(const std::string& text) {
  auto loaded = load_config_string(text, "acme.toml", kList);
  INFO((loaded ? std::string() : joined(loaded.error())));
  REQUIRE(loaded.has_value());
  return *loaded;
}

}  // namespace

TEST_CASE("config: a bus port may be a tty, a tcp:// or an rfc2217:// device server") {
  CHECK(loads(rieker_on("/dev/ttyUSB0")).buses[0].port == "/dev/ttyUSB0");
  CHECK(loads(rieker_on("tcp://192.168.1.20:4001")).buses[0].port == "tcp://192.168.1.20:4001");
  CHECK(loads(rieker_on("rfc2217://moxa-3.plant.local:950")).buses[0].port ==
        "rfc2217://moxa-3.plant.local:950");
  CHECK(loads(rieker_on("tcp://[fe80::1]:4001")).buses[0].port == "tcp://[fe80::1]:4001");
  // Nothing is resolved: a name no resolver knows is as good as any until the gateway starts.
  loads(rieker_on("tcp://no-such-host.invalid:4001"));
}

TEST_CASE("config: a device server URL in error is reported at the port key's line") {
  expect_error(rieker_on("tcp://gw:0"), 3, "bus[0].port",
               "the port 0 is out of range, expected 1..65535");
  expect_error(rieker_on("tcp://gw:65536"), 3, "bus[0].port",
               "the port 65536 is out of range, expected 1..65535");
  expect_error(rieker_on("telnet://gw:4001"), 3, "bus[0].port",
               "unknown scheme \"telnet://\", expected tcp:// (raw TCP) or rfc2217:// (Telnet "
               "COM-PORT-OPTION)");
  expect_error(rieker_on("tcp://:4001"), 3, "bus[0].port", "no host, expected tcp://HOST:PORT");
  expect_error(rieker_on("rfc2217://gw"), 3, "bus[0].port",
               "no port, expected rfc2217://gw:PORT (the device server's TCP port, 1..65535)");
  expect_error(rieker_on(""), 3, "bus[0].port",
               "empty, expected a tty path such as \"/dev/ttyUSB0\" or a device server such as "
               "\"tcp://192.168.1.20:4001\"");
  // Where the key is written, below other keys.
  const ConfigError e = only_error("[[bus]]\nname = \"line1\"\nprotocol = \"rieker\"\n"
                                   "port = \"tcp://gw:99999\"\n" +
                                   sensor_text("boom", "line1", 223, 1));
  CHECK(e.to_string() ==
        "test.toml:4:1: bus[0].port: the port 99999 is out of range, expected 1..65535");
}

TEST_CASE("config: two buses cannot use one device server port, whatever its spelling") {
  const std::string first = rieker_on("tcp://Moxa-3.plant.local:4001");
  expect_error(first + second_bus("rfc2217://moxa-3.PLANT.local:4001"), 12, "bus[1].port",
               "\"rfc2217://moxa-3.PLANT.local:4001\": the device server "
               "moxa-3.plant.local:4001 is already used by bus \"line1\" (line 1) "
               "(\"tcp://Moxa-3.plant.local:4001\")");
  expect_error(first + second_bus("tcp://Moxa-3.plant.local:4001"), 12, "bus[1].port",
               "\"tcp://Moxa-3.plant.local:4001\" is already used by bus \"line1\" (line 1)");
  expect_error(rieker_on("tcp://[FE80::1]:4001") + second_bus("tcp://[fe80::1]:4001"), 12,
               "bus[1].port",
               "\"tcp://[fe80::1]:4001\": the device server [fe80::1]:4001 is already used by "
               "bus \"line1\" (line 1) (\"tcp://[FE80::1]:4001\")");
  // Another port of the same server is another line.
  loads(first + second_bus("tcp://moxa-3.plant.local:4002"));
}

TEST_CASE("config: 9-bit framing over a device server is refused with the reason") {
  for (const std::string_view port : {"tcp://gw:4001", "rfc2217://gw:4001"}) {
    std::string text = dyna_bus("spectron-9bit", "baud = 9600\n") + dyna_sensor(1);
    text.replace(text.find("/dev/ttyS1"), 10, port);
    expect_error(
        text, 3, "bus[0].port",
        "\"" + std::string(port) +
            "\": 9-bit framing needs a local serial port: its ninth bit is the parity bit "
            "switched per byte (mark for the address byte, space for the data); raw TCP cannot "
            "switch the far port's parity at all, and RFC 2217's SET-PARITY is not applied in "
            "step with the bytes around it (docs/operations.md, \"Serial device servers\"); use "
            "protocol = \"spectron-modbus\" (Modbus-ASCII) with the same sensors, or a local "
            "serial port");
  }
  // The same sensors' Modbus-ASCII protocol goes over both, and 9-bit stays on a tty.
  std::string modbus = dyna_bus("spectron-modbus", "baud = 9600\n") + dyna_sensor(1);
  loads(modbus.replace(modbus.find("/dev/ttyS1"), 10, "rfc2217://gw:4001"));
  loads(dyna_bus("spectron-9bit", "baud = 9600\n") + dyna_sensor(1));
}

TEST_CASE("config: rs485 = true is refused on a device server's port, echo applies there") {
  expect_error(rieker_on("tcp://gw:4001", "rs485 = true\n"), 4, "bus[0].rs485",
               "true on a device server port (\"tcp://gw:4001\"): the server drives its own "
               "RS485 transmitter; leave rs485 out or false");
  expect_error(rieker_on("rfc2217://gw:4001", "rs485 = true\n"), 4, "bus[0].rs485",
               "true on a device server port (\"rfc2217://gw:4001\"): the server drives its own "
               "RS485 transmitter; leave rs485 out or false");
  const Config over_network =
      loads(rieker_on("tcp://gw:4001", "rs485 = false\necho = true\nlow_latency = true\n"));
  CHECK(over_network.buses[0].echo);
  CHECK_FALSE(over_network.buses[0].rs485_kernel);
  CHECK(loads(rieker_on("/dev/ttyS2", "rs485 = true\n")).buses[0].rs485_kernel);
}

TEST_CASE("config: devices that speak TCP need a tcp:// port, and no baud") {
  const Config plc = acme_loads(tcp_devices_on("tcp://10.0.0.7:502"));
  CHECK(plc.buses[0].port == "tcp://10.0.0.7:502");
  expect_acme_error(tcp_devices_on("/dev/ttyUSB0"), 3, "bus[0].port",
                    "\"/dev/ttyUSB0\" is a tty, but tcp-devices devices speak Modbus TCP "
                    "themselves: expected port = \"tcp://HOST:PORT\" (the device's address)");
  expect_acme_error(tcp_devices_on("rfc2217://10.0.0.7:502"), 3, "bus[0].port",
                    "rfc2217:// sets a serial port's rate and framing, but tcp-devices devices "
                    "speak Modbus TCP themselves: expected port = \"tcp://10.0.0.7:502\"");
  // The serial protocol beside it keeps its serial line's keys and checks over a network.
  std::string serial = tcp_devices_on("tcp://gw:4001", "baud = 9600\ngap_us = 500\n");
  serial.replace(serial.find("tcp-devices"), 11, "serial-devices");
  CHECK(acme_loads(serial).buses[0].baud == 9600);
  expect_acme_error(serial.replace(serial.find("baud = 9600"), 11, "baud = 19200"), 5,
                    "bus[0].baud", "19200 is not a serial-devices baud rate, expected one of 9600");
}

TEST_CASE("config: a bus of devices that speak TCP refuses every serial line key") {
  const std::string message = "a tcp-devices bus has no serial line: the devices speak Modbus TCP";
  for (const std::string_view key :
       {"baud = 9600", "parity = \"even\"", "stop_bits = 1", "gap_us = 0", "rs485 = false",
        "echo = true"}) {
    const std::string name(key.substr(0, key.find(' ')));
    expect_acme_error(tcp_devices_on("tcp://10.0.0.7:502", std::string(key) + "\n"), 5,
                      "bus[0]." + name, message);
  }
  // The keys of its reply timing and of its connection still apply.
  const Config plc = acme_loads(tcp_devices_on(
      "tcp://10.0.0.7:502", "timeout_ms = 200\nretries = 1\nreopen_min_ms = 1000\n"
                            "low_latency = false\n"));
  CHECK(plc.buses[0].timeout.count() == 200);
  CHECK(plc.buses[0].retries == 1);
}
