// Config text for the loader's tests: a valid base to append to, sensors and buses as text,
// and assertions on the one error a text holds. Shared by the config_*_test.cpp files.
#pragma once

#include <doctest/doctest.h>
#include <unistd.h>

#include <array>
#include <string>
#include <string_view>

#include "config/config_loader.h"

namespace tiltgate::test {

inline std::string joined(const ConfigErrors& errors) {
  std::string out;
  for (const ConfigError& e : errors) out += e.to_string() + "\n";
  return out;
}

// The machine's host name: what the [mqtt] and [sparkplug] defaults are made of.
inline std::string this_host() {
  std::array<char, 256> name{};
  REQUIRE(gethostname(name.data(), name.size() - 1) == 0);
  return name.data();
}

inline ConfigErrors errors_of(std::string_view text) {
  auto loaded = load_config_string(text, "test.toml", registered_families());
  REQUIRE_FALSE(loaded.has_value());
  return loaded.error();
}

// The one error `text` holds.
inline ConfigError only_error(std::string_view text) {
  const ConfigErrors errors = errors_of(text);
  INFO(joined(errors));
  REQUIRE(errors.size() == 1);
  return errors[0];
}

inline Config loads(std::string_view text) {
  auto loaded = load_config_string(text, "test.toml", registered_families());
  INFO((loaded ? std::string() : joined(loaded.error())));
  REQUIRE(loaded.has_value());
  return *loaded;
}

// Lines 1..8: one Rieker bus and one sensor, valid. Tests append from line 9 on.
constexpr std::string_view kValid = R"([[bus]]
name = "line1"
port = "/dev/ttyUSB0"
[[sensor]]
name = "boom"
bus = "line1"
model = "h6"
address = 223
)";

inline std::string valid_plus(std::string_view rest) {
  return std::string(kValid) + "unit_id = 1\n" + std::string(rest);
}

// A [[sensor]] table of 6 lines: header, name, bus, model "h6", address, unit_id.
inline std::string sensor_text(std::string_view name, std::string_view bus, int address, int unit_id) {
  return "[[sensor]]\nname = \"" + std::string(name) + "\"\nbus = \"" + std::string(bus) +
         "\"\nmodel = \"h6\"\naddress = " + std::to_string(address) +
         "\nunit_id = " + std::to_string(unit_id) + "\n";
}

// Lines 1..4 and then `more`: a Spectron bus "s".
inline std::string dyna_bus(std::string_view protocol, std::string_view more) {
  return "[[bus]]\nname = \"s\"\nport = \"/dev/ttyS1\"\nprotocol = \"" + std::string(protocol) +
         "\"\n" + std::string(more);
}

// A Dyna on bus "s", unit 1; its address is the 5th line.
inline std::string dyna_sensor(int address) {
  return "[[sensor]]\nname = \"d\"\nbus = \"s\"\nmodel = \"dyna\"\naddress = " +
         std::to_string(address) + "\nunit_id = 1\n";
}

// `text` holds exactly one error: at `line`, under `key`, saying `message`.
inline void expect_error(const std::string& text, int line, std::string_view key,
                  std::string_view message) {
  CAPTURE(text);
  const ConfigError e = only_error(text);
  CHECK(e.line == line);
  CHECK(e.key == key);
  CHECK(e.message == message);
}

// The valid text with `keys` added to its bus from line 4 on.
inline std::string with_bus_keys(std::string_view keys) {
  std::string text = valid_plus("");
  return text.insert(text.find("[[sensor]]"), keys);
}


}  // namespace tiltgate::test
