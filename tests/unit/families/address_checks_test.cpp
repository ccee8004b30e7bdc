// Addresses a driver refuses before anything is sent (the Rieker broadcast and master
// addresses), and which writes move a sensor, so the bus can refuse an address another of its
// sensors has (line_scheduling/bus_scheduler.h).
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>

#include "rieker/codec.h"
#include "rieker/rieker_driver.h"
#include "sim/support/run_coroutine.h"
#include "spectron/dyna_driver.h"
#include "spectron/eeprom_map.h"
#include "unit/support/fake_bus.h"
#include "spectron/setting_ids.h"

using namespace tiltgate;

TEST_CASE("a Rieker sensor is never given the broadcast address or the bus master's") {
  rieker::RiekerDriverOptions options;
  options.address = 223;
  options.master_address = 5;
  const rieker::RiekerDriver driver(options);
  CHECK(driver.check_write(WriteTarget::bus_address, rieker::kBroadcastAddress).error().kind ==
        WriteErrorKind::bad_value);
  CHECK(driver.check_write(WriteTarget::bus_address, 5).error().kind == WriteErrorKind::bad_value);
  CHECK(driver.check_write(WriteTarget::bus_address, 6).has_value());
}

TEST_CASE("a write to bus_address moves the sensor, other settings do not") {
  rieker::RiekerDriverOptions options;
  options.address = 223;
  const rieker::RiekerDriver driver(options);
  CHECK(driver.address_after(WriteTarget::bus_address, 300) == 300u);
  CHECK(driver.address_after(WriteTarget::filter, 3) == std::nullopt);
  CHECK(driver.address_after(WriteTarget::zero_x, 223) == std::nullopt);
}

TEST_CASE("a Dyna EEPROM window write moves the module when the address location is selected") {
  boost::asio::io_context io;
  test::FakeLine line(io.get_executor());
  // Selecting a location reads it from the module: a 9-bit module answers a decimal line.
  line.reply = [](const LineRequest&) {
    const std::string text = "7\r\n";
    return std::vector<std::uint8_t>(text.begin(), text.end());
  };
  spectron::DynaDriver driver(spectron::DynaDriverOptions{});
  CHECK(driver.address_after(WriteTarget::bus_address, 7) == 7u);
  CHECK(driver.address_after(spectron::setting::eeprom_value, 7) == std::nullopt);  // none selected
  auto selected = test::run_coroutine(
      io, driver.write(line, spectron::setting::eeprom_location, spectron::eeprom::kModuleAddress));
  REQUIRE(selected.has_value());
  CHECK(driver.address_after(spectron::setting::eeprom_value, 7) == 7u);
  selected = test::run_coroutine(
      io, driver.write(line, spectron::setting::eeprom_location, spectron::eeprom::kSensorOffset));
  REQUIRE(selected.has_value());
  CHECK(driver.address_after(spectron::setting::eeprom_value, 7) == std::nullopt);
  CHECK(line.stats().attempts == 2);  // each selection read its location from the module
}
