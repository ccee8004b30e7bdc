// [[bus]] parity and stop_bits: accepted only where the protocol lets a bus choose its framing
// (Modbus RTU), defaulting as the Modbus serial line spec says, and the gap derived from the
// baud and framing unless gap_us is given. Two protocols defined only here, one of each kind.
#include <doctest/doctest.h>

#include <array>
#include <string>
#include <string_view>

#include "config/config_loader.h"
#include "driver/family.h"
#include "gateway/serial_options.h"
#include "mapping/common_block.h"
#include "mapping/register_map.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

constexpr std::array<std::int64_t, 2> kBauds{9600, 19200};

// A gap that shows which baud and framing it was computed from.
std::chrono::microseconds gap_from(std::uint32_t baud, Framing framing) {
  return std::chrono::microseconds{baud / 100 + int(framing)};
}

const ProtocolDescriptor kProtocols[] = {
    {
        .name = "chosen-bus",
        .short_name = "chosen",
        .title = "Chosen",
        .framing = Framing::eight_even_one,
        .bauds = kBauds,
        .default_baud = 19200,
        .addresses = {1, 247},
        .master_addresses = std::nullopt,
        .min_gap = std::chrono::microseconds{0},
        .bus_chooses_framing = true,
        .default_gap = gap_from,
    },
    {
        .name = "fixed-bus",
        .short_name = "fixed",
        .title = "Fixed",
        .framing = Framing::eight_none_one,
        .bauds = kBauds,
        .default_baud = 19200,
        .addresses = {1, 247},
        .master_addresses = std::nullopt,
        .min_gap = std::chrono::microseconds{0},
        .bus_chooses_framing = false,
        .default_gap = nullptr,
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

std::string bus_config(std::string_view protocol, std::string_view extra) {
  return "[[bus]]\nname = \"east\"\nport = \"/dev/ttyS7\"\nprotocol = \"" + std::string(protocol) +
         "\"\nbaud = 9600\n" + std::string(extra) +
         "\n[[sensor]]\nname = \"s\"\nbus = \"east\"\nmodel = \"plain\"\naddress = 1\nunit_id = 1\n";
}

BusConfig load_bus(std::string_view protocol, std::string_view extra) {
  auto loaded = load_config_string(bus_config(protocol, extra), "bus.toml", kList);
  REQUIRE_MESSAGE(loaded.has_value(),
                  (loaded ? std::string() : loaded.error().front().to_string()));
  REQUIRE(loaded->buses.size() == 1);
  return loaded->buses[0];
}

Framing framing_of(std::string_view extra) {
  const BusConfig bus = load_bus("chosen-bus", extra);
  return serial_options_from(kList, bus).framing;
}

std::string first_error(std::string_view protocol, std::string_view extra) {
  auto loaded = load_config_string(bus_config(protocol, extra), "bus.toml", kList);
  REQUIRE_FALSE(loaded.has_value());
  return loaded.error().front().to_string();
}

}  // namespace

TEST_CASE("a bus that chooses its framing defaults to even parity and one stop bit") {
  CHECK(framing_of("") == Framing::eight_even_one);
  CHECK(framing_of("parity = \"even\"\n") == Framing::eight_even_one);
}

TEST_CASE("odd parity is 8O1, and no parity means two stop bits unless stop_bits says one") {
  CHECK(framing_of("parity = \"odd\"\n") == Framing::eight_odd_one);
  CHECK(framing_of("parity = \"none\"\n") == Framing::eight_none_two);
  CHECK(framing_of("parity = \"none\"\nstop_bits = 2\n") == Framing::eight_none_two);
  CHECK(framing_of("parity = \"none\"\nstop_bits = 1\n") == Framing::eight_none_one);
  CHECK(framing_of("parity = \"odd\"\nstop_bits = 1\n") == Framing::eight_odd_one);
}

TEST_CASE("parity with two stop bits and unknown parities are config errors") {
  CHECK(first_error("chosen-bus", "parity = \"even\"\nstop_bits = 2\n") ==
        "bus.toml:7:1: bus[0].stop_bits: 2 with parity is not supported, expected 1 (or parity "
        "= \"none\")");
  CHECK(first_error("chosen-bus", "stop_bits = 3\n").find("bus[0].stop_bits") !=
        std::string::npos);
  CHECK(first_error("chosen-bus", "parity = \"mark\"\n").find("bus[0].parity") !=
        std::string::npos);
}

TEST_CASE("parity and stop_bits on a bus whose protocol fixes its framing are refused") {
  CHECK(first_error("fixed-bus", "parity = \"odd\"\n") ==
        "bus.toml:6:1: bus[0].parity: applies to chosen-bus buses only, not fixed-bus");
  CHECK(first_error("fixed-bus", "stop_bits = 2\n") ==
        "bus.toml:6:1: bus[0].stop_bits: applies to chosen-bus buses only, not fixed-bus");
  CHECK(serial_options_from(kList, load_bus("fixed-bus", "")).framing == Framing::eight_none_one);
}

TEST_CASE("the gap defaults to the protocol's, from the bus's baud and framing") {
  CHECK(load_bus("chosen-bus", "").gap ==
        std::chrono::microseconds{96 + int(Framing::eight_even_one)});
  CHECK(load_bus("chosen-bus", "parity = \"none\"\n").gap ==
        std::chrono::microseconds{96 + int(Framing::eight_none_two)});
  CHECK(load_bus("chosen-bus", "gap_us = 4000\n").gap == 4000us);
  CHECK(load_bus("fixed-bus", "").gap == 1000us);  // no default_gap: 1 ms
}
