// The text the command line prints of `info`'s and `set`'s events (commission/event_text.h):
// the lines these commands printed before they reported events, byte for byte.
#include <doctest/doctest.h>

#include "commission/event_text.h"

namespace tiltgate {
namespace {

SensorReadingEvent reading_at(std::uint32_t address, PollResult result, std::string status) {
  SensorReadingEvent reading;
  reading.address = address;
  reading.model = "h6";
  reading.serial = "962285";
  reading.firmware = "Rev A.8";
  reading.lock_level = 0;
  reading.result = result;
  reading.status = std::move(status);
  reading.angle_x = 1.5;
  reading.angle_y = -2.25;
  return reading;
}

TEST_CASE("a sensor that gave a reading shows its identity and angles, one fact a line") {
  CHECK(sensor_reading_text(reading_at(223, PollResult::reading, "ok")) ==
        "address:    223\n"
        "model:      h6\n"
        "serial:     962285\n"
        "firmware:   Rev A.8\n"
        "lock level: 0\n"
        "angle x:    1.500 deg\n"
        "angle y:    -2.250 deg\n"
        "tilt:       2.703 deg\n");
}

TEST_CASE("a sensor that gave no reading shows its address and status only") {
  CHECK(sensor_reading_text(reading_at(224, PollResult::silent, "no reply")) ==
        "address:    224\nstatus:     no reply\n");
  CHECK(sensor_reading_text(reading_at(7, PollResult::refused, "refused: NAK 2 (locked)")) ==
        "address:    7\nstatus:     refused: NAK 2 (locked)\n");
}

TEST_CASE("a device without its driver shows what it said of itself, and no reply when silent") {
  SensorReadingEvent told;
  told.address = 3;
  told.result = PollResult::no_reading;
  told.status = "answered";
  told.self_report = "vendor:     ACME\n";
  CHECK(sensor_reading_text(told) == "address:    3\nvendor:     ACME\n");
  SensorReadingEvent silent;
  silent.address = 4;
  silent.result = PollResult::silent;
  silent.status = "no reply";
  CHECK(sensor_reading_text(silent) == "address:    4\nstatus:     no reply\n");
}

TEST_CASE("set's lines: acknowledged, the move, the restart, the file, the values read back") {
  CHECK(setting_applied_text({"zero-here", true, 223}) ==
        "zero-here --permanent at address 223: acknowledged\n");
  CHECK(setting_applied_text({"filter 5", false, 7}) == "filter 5 at address 7: acknowledged\n");
  CHECK(address_moved_text({223, 9, ""}) == "the sensor now answers at address 9\n");
  CHECK(address_moved_text({223, 9, "line1/boom"}) ==
        "gateway: sensor line1/boom is polled at address 9 from now on\n"
        "the sensor now answers at address 9\n");
  CHECK(sensor_restarted_text({std::nullopt, true, 125000}) == "the sensor restarted\n");
  CHECK(sensor_restarted_text({57600u, true, 57600}) ==
        "the sensor restarted at 57600 baud; the line follows it\n");
  CHECK(sensor_restarted_text({57600u, false, 125000}) ==
        "the sensor restarted at 57600 baud; the gateway's bus stays at 125000 baud, so it no "
        "longer answers there: set the others, then the bus's baud in the configuration\n");
  CHECK(config_updated_text({"g.toml",
                             {"updated g.toml: sensor boom address 223 -> 7",
                              "updated g.toml: bus line1 baud 125000 -> 57600"}}) ==
        "updated g.toml: sensor boom address 223 -> 7\n"
        "updated g.toml: bus line1 baud 125000 -> 57600\n");
  CHECK(settings_read_text({7, {{"filter", 5.0}, {"zero x", 0.25}, {"offset", std::nullopt}}}) ==
        "filter:     5\n"
        "zero x:     0.25\n"
        "offset:     -\n");
}

}  // namespace
}  // namespace tiltgate
