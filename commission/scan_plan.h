// `tiltgate scan`'s pure parts: which addresses and rates to probe, how long to wait for each
// probe, and how the sensors found are shown (rows, summary, progress bar) and written out as a
// configuration. The command (scan_command.cpp) does the probing.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "commission/configured_units.h"
#include "config/config.h"
#include "driver/expected.h"
#include "driver/family.h"

namespace tiltgate {

struct ScanOptions {
  bool auto_baud = false;  // --baud auto: every rate the protocol allows
  std::optional<std::int64_t> from;
  std::optional<std::int64_t> to;
  std::string config_out;  // write a configuration of the sensors found; empty: none
  bool force = false;      // overwrite config_out
  bool broadcast = false;  // ask every sensor at once (one sensor on the bus only)
  std::optional<std::int64_t> probe_timeout_ms;
};

// Added to a protocol's probe time for the default probe time-out: a USB RS485 adapter holds
// short replies back for a few milliseconds (FTDI's latency timer), and the machine may be busy.
inline constexpr std::chrono::milliseconds kProbeAllowance{10};

// The addresses to probe: --from..--to, each bound defaulting to the protocol's scan range
// (ScanDescriptor::first, last); without either, that range and the factory addresses. Sorted,
// each once. An error names the option.
Expected<std::vector<std::uint32_t>, std::string> scan_addresses(
    const ProtocolDescriptor& protocol, std::optional<std::int64_t> from,
    std::optional<std::int64_t> to);

// The rates to try: the bus's own, and with auto every other rate of the protocol after it,
// in the protocol's order.
std::vector<std::uint32_t> scan_bauds(const ProtocolDescriptor& protocol, std::uint32_t bus_baud,
                                      bool auto_baud);

// Why --baud auto cannot be used on the bus at `port`, or none. Over rfc2217:// the gateway
// sets the device server's rate for each try, as on a tty; over raw TCP (tcp://) the rate is
// the server's own setting, which the gateway cannot change; a bus whose devices speak TCP
// has no rate at all.
std::optional<std::string> auto_baud_refusal(const ProtocolDescriptor& protocol,
                                             std::string_view port);

// The probe time at `baud`, rounded up to whole milliseconds, plus kProbeAllowance.
std::chrono::milliseconds default_probe_timeout(const ProtocolDescriptor& protocol,
                                                std::uint32_t baud);

// One address as the scan found it.
struct FoundSensor {
  std::uint32_t address = 0;
  std::uint32_t baud = 0;
  // Bytes that failed their checksum came back: probably two sensors at this address.
  bool collision = false;
  std::string detail;  // what the probe or the identity read said, when worth telling
  // What the family's driver read; empty / none when it could not.
  std::string model;
  std::string serial;
  std::string firmware;
  std::optional<std::uint16_t> lock_level;
};

// With --baud auto, a sensor that answers at several rates (one that detects the rate, or a
// simulator that takes any) is found once per rate. The same serial is the same sensor: it is
// kept where it was found first (the first rate tried), its rows at later rates dropped.
// Sensors whose serial could not be read are all kept.
struct RepeatedSensor {
  std::uint32_t address = 0;
  std::string serial;
  std::uint32_t kept_baud = 0;
  std::vector<std::uint32_t> other_bauds;
};
std::vector<RepeatedSensor> drop_repeated_sensors(std::vector<FoundSensor>& found);
// "note: serial 10001 (address 1) answered at 4800, 9600 baud too: listed once, at 38400 baud".
std::string repeated_note(const RepeatedSensor& repeated);

// The table: a header and one row per address (answered, or a probable collision).
std::string scan_header();
std::string scan_row(const FoundSensor& sensor);

// "3 sensor(s) found at 125000 baud: 101, 223, 224; 1 probable collision (address 5);
// 256 address(es) probed in 4.1 s".
std::string scan_summary(const std::vector<FoundSensor>& found, std::size_t probes,
                         std::chrono::milliseconds took);

// One line that a terminal redraws in place: a bar, the count and the addresses found so far,
// cut to `width` characters.
std::string progress_line(std::size_t done, std::size_t total, std::uint32_t baud,
                          const std::vector<FoundSensor>& found, std::size_t width = 79);

// The configuration `--config-out` writes: one [[bus]] as scanned (at the rate where the first
// sensor was found), one [[sensor]] per sensor found at that rate that `configured` has not
// (sensor_tables), named sensor_ADDRESS, with comments on what to edit. `sensor_keys` are the
// family's keys every sensor must give (a device profile), with the values the scan was given.
// Sensors found at another rate, collisions and sensors configured already are listed in
// comments.
struct SensorKeyValue {
  std::string key;
  std::string value;
};
std::string scan_config_text(const BusConfig& bus, const std::vector<FoundSensor>& found,
                             const std::vector<SensorKeyValue>& sensor_keys,
                             const ConfiguredUnits& configured = {});

// The sensors found at that rate, each with what it was made from: what the web console offers
// to add to the served configuration. A sensor whose address `configured` has on the bus is
// `configured_as` that sensor's name, with no table (it is there already). Each other gets a
// [[sensor]] table with the lowest unit id that no configured unit has and no earlier table of
// this scan got (free_unit_ids): it can be added as it is, and `tiltgate check` takes it.
struct SensorTable {
  std::uint32_t address = 0;
  std::string model, serial, firmware;
  std::string text;  // the table's TOML, "[[sensor]]" to its last key; empty when configured
  std::string configured_as;          // the configured sensor at this address; empty: none
  std::uint8_t proposed_unit_id = 0;  // the table's unit id; 0: none (configured, or none free)
};
std::vector<SensorTable> sensor_tables(const BusConfig& bus, const std::vector<FoundSensor>& found,
                                       const std::vector<SensorKeyValue>& sensor_keys,
                                       const ConfiguredUnits& configured = {});

}  // namespace tiltgate
