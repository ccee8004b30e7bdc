#include "commission/scan_plan.h"

#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commission/commission_options.h"
#include "commission/reading_format.h"
#include "device_server/port_url.h"

namespace tiltgate {

namespace {

constexpr std::string_view kScanRowFormat = "{:<8} {:>7} {:<11} {:<12} {:<9} {:<5} {}";

Expected<std::uint32_t, std::string> checked_bound(std::string_view option, std::int64_t value,
                                                   const ProtocolDescriptor& protocol) {
  if (value < protocol.addresses.min || value > protocol.addresses.max)
    return Unexpected{fmt::format("{}: {} is outside the {} protocol's addresses {}..{}", option,
                                  value, protocol.name, protocol.addresses.min,
                                  protocol.addresses.max)};
  return std::uint32_t(value);
}

std::vector<std::uint32_t> addresses_of(const std::vector<FoundSensor>& found, bool collisions) {
  std::vector<std::uint32_t> out;
  for (const FoundSensor& s : found)
    if (s.collision == collisions) out.push_back(s.address);
  return out;
}

const char* parity_name(Framing framing) {
  switch (framing) {
    case Framing::eight_even_one: return "even";
    case Framing::eight_odd_one: return "odd";
    default: return "none";
  }
}

}  // namespace

Expected<std::vector<std::uint32_t>, std::string> scan_addresses(
    const ProtocolDescriptor& protocol, std::optional<std::int64_t> from,
    std::optional<std::int64_t> to) {
  const ScanDescriptor& scan = protocol.scan;
  auto first = checked_bound("--from", from.value_or(scan.first), protocol);
  if (!first) return Unexpected{first.error()};
  auto last = checked_bound("--to", to.value_or(scan.last), protocol);
  if (!last) return Unexpected{last.error()};
  if (*first > *last)
    return Unexpected{fmt::format("--from: {} is past --to {}{}", *first, *last,
                                  to ? "" : " (the default end: give --to)")};
  std::vector<std::uint32_t> addresses;
  addresses.reserve(*last - *first + 1 + scan.factory_addresses.size());
  for (std::uint32_t a = *first; a <= *last; ++a) addresses.push_back(a);
  if (!from && !to) {
    for (const std::uint32_t a : scan.factory_addresses)
      if (a < *first || a > *last) addresses.push_back(a);
  }
  std::sort(addresses.begin(), addresses.end());
  addresses.erase(std::unique(addresses.begin(), addresses.end()), addresses.end());
  return addresses;
}

std::vector<std::uint32_t> scan_bauds(const ProtocolDescriptor& protocol, std::uint32_t bus_baud,
                                      bool auto_baud) {
  std::vector<std::uint32_t> bauds{bus_baud};
  if (!auto_baud) return bauds;
  for (const std::int64_t b : protocol.bauds)
    if (std::uint32_t(b) != bus_baud) bauds.push_back(std::uint32_t(b));
  return bauds;
}

std::optional<std::string> auto_baud_refusal(const ProtocolDescriptor& protocol,
                                             std::string_view port) {
  if (protocol.devices_speak_tcp)
    return fmt::format("--baud auto: a {} bus has no serial line and no rate: the devices speak "
                       "{}",
                       protocol.name, protocol.title);
  const auto address = parse_port(port);
  if (address && address->scheme == PortScheme::tcp)
    return fmt::format(
        "--baud auto: not over tcp:// (raw TCP cannot change the device server's rate: it is "
        "the server's own setting); use rfc2217://{} if the server offers RFC 2217 (the rate is "
        "then set for each try), or set each rate on the server and scan with --baud RATE",
        address->endpoint());
  return std::nullopt;
}

std::chrono::milliseconds default_probe_timeout(const ProtocolDescriptor& protocol,
                                                std::uint32_t baud) {
  const auto wire = protocol.scan.probe_time ? protocol.scan.probe_time(baud)
                                             : std::chrono::microseconds{0};
  return std::chrono::ceil<std::chrono::milliseconds>(wire) + kProbeAllowance;
}

std::vector<RepeatedSensor> drop_repeated_sensors(std::vector<FoundSensor>& found) {
  std::vector<RepeatedSensor> repeated;
  std::vector<FoundSensor> kept;
  for (FoundSensor& s : found) {
    // The same sensor at another rate: its serial at its address. Two devices at one rate are
    // two, even with one serial (a cloned profile, a simulator): both are listed.
    const auto first = std::find_if(kept.begin(), kept.end(), [&](const FoundSensor& k) {
      return !s.serial.empty() && !s.collision && !k.collision && k.serial == s.serial &&
             k.address == s.address && k.baud != s.baud;
    });
    if (first == kept.end()) {
      kept.push_back(std::move(s));
      continue;
    }
    auto entry = std::find_if(repeated.begin(), repeated.end(),
                              [&](const RepeatedSensor& r) { return r.serial == s.serial; });
    if (entry == repeated.end()) {
      repeated.push_back(RepeatedSensor{first->address, first->serial, first->baud, {}});
      entry = repeated.end() - 1;
    }
    entry->other_bauds.push_back(s.baud);
  }
  found = std::move(kept);
  return repeated;
}

std::string repeated_note(const RepeatedSensor& r) {
  return fmt::format("note: serial {} (address {}) answered at {} baud too: one sensor, listed "
                     "once, at {} baud",
                     r.serial, r.address, fmt::join(r.other_bauds, ", "), r.kept_baud);
}

// A rate for the table and the summaries; "-" for a bus without a serial line (baud 0: devices
// that speak TCP themselves).
std::string baud_text(std::uint32_t baud) { return baud == 0 ? "-" : fmt::format("{}", baud); }

std::string scan_header() {
  return fmt::format(fmt::runtime(kScanRowFormat), "ADDRESS", "BAUD", "MODEL", "SERIAL", "FIRMWARE",
                     "LOCK", "STATUS");
}

std::string scan_row(const FoundSensor& s) {
  std::string status = s.collision ? "probable collision (two sensors at this address?)" : "ok";
  if (!s.detail.empty()) status += fmt::format(": {}", s.detail);
  return fmt::format(fmt::runtime(kScanRowFormat), s.address, baud_text(s.baud), or_dash(s.model),
                     or_dash(s.serial), or_dash(s.firmware),
                     s.lock_level ? fmt::format("{}", *s.lock_level) : std::string("-"), status);
}

std::string scan_summary(const std::vector<FoundSensor>& found, std::size_t probes,
                         std::chrono::milliseconds took) {
  const std::vector<std::uint32_t> sensors = addresses_of(found, false);
  const std::vector<std::uint32_t> collisions = addresses_of(found, true);
  std::vector<std::uint32_t> bauds;
  for (const FoundSensor& s : found)
    if (!s.collision && std::find(bauds.begin(), bauds.end(), s.baud) == bauds.end())
      bauds.push_back(s.baud);
  std::string text = fmt::format("{} sensor(s) found", sensors.size());
  if (!sensors.empty() && bauds == std::vector<std::uint32_t>{0})
    text += fmt::format(": {}", fmt::join(sensors, ", "));
  else if (!sensors.empty())
    text += fmt::format(" at {} baud: {}", fmt::join(bauds, "/"), fmt::join(sensors, ", "));
  if (!collisions.empty())
    text += fmt::format("; {} probable collision(s) (address {})", collisions.size(),
                        fmt::join(collisions, ", "));
  text += fmt::format("; {} probe(s) in {:.1f} s", probes, double(took.count()) / 1000.0);
  return text;
}

std::string progress_line(std::size_t done, std::size_t total, std::uint32_t baud,
                          const std::vector<FoundSensor>& found, std::size_t width) {
  constexpr std::size_t kBar = 20;
  const std::size_t filled = total == 0 ? kBar : std::min(kBar, done * kBar / total);
  std::string line = fmt::format("[{}{}] {}/{}{}, found: ", std::string(filled, '#'),
                                 std::string(kBar - filled, '.'), done, total,
                                 baud == 0 ? std::string() : fmt::format(" at {} baud", baud));
  const std::vector<std::uint32_t> sensors = addresses_of(found, false);
  line += sensors.empty() ? std::string("none") : fmt::format("{}", fmt::join(sensors, " "));
  if (line.size() > width) line = line.substr(0, width - 3) + "...";
  return line;
}

namespace {

// The rate the configuration is written at: the first sensor's that answered clearly.
std::uint32_t configured_baud(const BusConfig& bus, const std::vector<FoundSensor>& found) {
  const auto first = std::find_if(found.begin(), found.end(),
                                  [](const FoundSensor& s) { return !s.collision; });
  return first == found.end() ? bus.baud : first->baud;
}

std::string written_bus_name(const BusConfig& bus) {
  return bus.name == kCommandLineBus ? "line1" : bus.name;
}

}  // namespace

std::vector<SensorTable> sensor_tables(const BusConfig& bus, const std::vector<FoundSensor>& found,
                                       const std::vector<SensorKeyValue>& sensor_keys,
                                       const ConfiguredUnits& configured) {
  const std::uint32_t baud = configured_baud(bus, found);
  const std::string bus_name = written_bus_name(bus);
  const auto listed = [&](const FoundSensor& s) { return !s.collision && s.baud == baud; };
  const auto configured_as = [&](const FoundSensor& s) {
    const auto at = configured.on_bus.find(s.address);
    return at == configured.on_bus.end() ? std::string() : at->second;
  };
  const std::size_t new_sensors = std::count_if(found.begin(), found.end(), [&](const auto& s) {
    return listed(s) && configured_as(s).empty();
  });
  const std::vector<std::uint8_t> unit_ids = free_unit_ids(configured.unit_ids, new_sensors);
  std::size_t next_unit_id = 0;
  std::vector<SensorTable> tables;
  for (const FoundSensor& s : found) {
    if (!listed(s)) continue;
    SensorTable table;
    table.address = s.address;
    table.model = s.model;
    table.serial = s.serial;
    table.firmware = s.firmware;
    table.configured_as = configured_as(s);
    if (!table.configured_as.empty()) {
      tables.push_back(std::move(table));
      continue;
    }
    std::string text = fmt::format("[[sensor]]\nname = {}    # edit: what it measures\n",
                                   toml_string(fmt::format("sensor_{}", s.address)));
    text += fmt::format("bus = {}\n", toml_string(bus_name));
    if (!s.model.empty()) text += fmt::format("model = {}\n", toml_string(s.model));
    text += fmt::format("address = {}\n", s.address);
    if (next_unit_id < unit_ids.size()) {
      table.proposed_unit_id = unit_ids[next_unit_id++];
      text += fmt::format("unit_id = {}    # edit: the PLC's unit id for it\n",
                          table.proposed_unit_id);
    } else {
      text += "# unit_id: none of 1..247 is free in the configuration; free one, then give it\n";
    }
    for (const SensorKeyValue& key : sensor_keys)
      text += fmt::format("{} = {}\n", key.key, toml_string(key.value));
    // The gateway serves this sensor only while this serial answers at its address.
    if (!s.serial.empty())
      text += fmt::format("serial = {}    # firmware {}\n", toml_string(s.serial),
                          or_dash(s.firmware));
    else if (!s.firmware.empty())
      text += fmt::format("# serial -, firmware {}\n", s.firmware);
    table.text = std::move(text);
    tables.push_back(std::move(table));
  }
  return tables;
}

std::string scan_config_text(const BusConfig& bus, const std::vector<FoundSensor>& found,
                             const std::vector<SensorKeyValue>& sensor_keys,
                             const ConfiguredUnits& configured) {
  const std::uint32_t baud = configured_baud(bus, found);
  std::string text =
      "# Written by `tiltgate scan`: the sensors that answered on this bus.\n"
      "# Edit each sensor's name (what it measures, e.g. \"boom\") and its unit_id (the Modbus\n"
      "# unit id the PLC reads it at), then: tiltgate check --config THIS_FILE\n";
  text += fmt::format("\n[[bus]]\nname = {}\nport = {}\nprotocol = {}\n",
                      toml_string(written_bus_name(bus)), toml_string(bus.port),
                      toml_string(bus.protocol));
  // A bus without a serial line (devices that speak TCP) has no rate to write.
  if (baud != 0) text += fmt::format("baud = {}\n", baud);
  if (bus.framing)
    text += fmt::format("parity = {}\nstop_bits = {}\n", toml_string(parity_name(*bus.framing)),
                        stop_bits_of(*bus.framing));
  if (bus.master_address != 0) text += fmt::format("master_address = {}\n", bus.master_address);
  for (const SensorTable& table : sensor_tables(bus, found, sensor_keys, configured)) {
    if (table.configured_as.empty())
      text += "\n" + table.text;
    else
      text += fmt::format("\n# Address {}: already configured as {}: not added again.\n",
                          table.address, toml_string(table.configured_as));
  }
  for (const FoundSensor& s : found) {
    if (s.collision)
      text += fmt::format(
          "\n# Address {}: garbled replies, probably two sensors at one address. Power one of\n"
          "# them at a time, give it a free address (tiltgate set), then scan again.\n",
          s.address);
    else if (s.baud != baud)
      text += fmt::format(
          "\n# Address {} answered at {} baud, not {}: set it to {} baud (tiltgate set) and\n"
          "# scan again to add it.\n",
          s.address, s.baud, baud, baud);
  }
  return text;
}

}  // namespace tiltgate
