// `tiltgate scan`: finds the sensors on a bus. Each address of the range is probed with the
// protocol's own probe (driver/scan.h) and a short time-out; each address that answered is
// identified through the family's driver, as `info` does. With --baud auto, every rate the
// protocol allows is tried in turn.
#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <iostream>
#include <unistd.h>

#include "commission/commands.h"
#include "commission/commission_run.h"
#include "gateway/driver_registry.h"
#include "commission/model_detection.h"
#include "commission/scan_plan.h"

namespace tiltgate {

namespace {

// Scans of more probes than this show a progress bar on a terminal.
constexpr std::size_t kLongScan = 64;
constexpr std::chrono::milliseconds kRedrawEvery{100};

using Clock = std::chrono::steady_clock;

// What the scan needs besides the bus: a sensor standing for those to be found (its model and
// the family's keys, such as a device profile), when the options gave one.
struct ScanTarget {
  CommissionTarget bus;
  std::optional<SensorConfig> model_sensor;
};

// A command-line bus gets a stand-in sensor so that --model and the family's keys (--device)
// are read and checked as for any sensor; a family whose sensors need a key the options do not
// give is scanned without one.
Expected<ScanTarget, UsageErrors> resolve_scan_target(BusOptions options, bool auto_baud,
                                                      FamilyList families) {
  options.sensors_optional = true;
  if (options.config.empty()) {
    const ProtocolEntry entry = find_protocol(
        families, options.protocol.empty() ? families.front()->protocols.front().name
                                           : std::string_view(options.protocol));
    // --baud auto starts at the factory rate, else at the protocol's first.
    if (entry.protocol && auto_baud && !options.baud && !entry.protocol->bauds.empty())
      options.baud = entry.protocol->default_baud.value_or(entry.protocol->bauds.front());
    if (entry.protocol && options.addresses.empty()) {
      BusOptions with_sensor = options;
      std::int64_t address = entry.protocol->addresses.min;
      if (options.master_address && *options.master_address == address) ++address;
      with_sensor.addresses = {address};
      if (auto target = resolve_bus_options(with_sensor, families)) {
        ScanTarget out{*target, target->sensors.front()};
        out.bus.sensors.clear();
        return out;
      }
    }
  }
  auto target = resolve_bus_options(options, families);
  if (!target) {
    // A bus scanned from the command line has no sensors by design: the loader's complaint
    // about that only hides the real problem (say a protocol without a default rate and no
    // --baud).
    UsageErrors errors = target.error();
    if (options.config.empty())
      std::erase_if(errors, [](const std::string& e) {
        return e.starts_with("--sensor: no [[sensor]]");
      });
    return Unexpected{std::move(errors)};
  }
  ScanTarget out{*target, std::nullopt};
  if (!out.bus.sensors.empty()) out.model_sensor = out.bus.sensors.front();
  return out;
}

// Shows how far the scan is, redrawn in place on stderr; nothing when not a terminal, unless
// asked for as lines (ScanOptions::progress_lines).
class Progress {
 public:
  Progress(bool shown, bool lines) : shown_(shown), lines_(lines) {}
  ~Progress() { clear(); }
  void show(std::size_t done, std::size_t total, std::uint32_t baud,
            const std::vector<FoundSensor>& found) {
    if (lines_) {
      std::cerr << "progress " << done << " " << total << "\n" << std::flush;
      return;
    }
    if (!shown_) return;
    const auto now = Clock::now();
    if (done < total && now - drawn_at_ < kRedrawEvery) return;
    drawn_at_ = now;
    std::cerr << "\r\x1b[2K" << progress_line(done, total, baud, found) << std::flush;
    drawn_ = true;
  }
  void clear() {
    if (drawn_) std::cerr << "\r\x1b[2K" << std::flush;
    drawn_ = false;
  }

 private:
  bool shown_;
  bool lines_;
  bool drawn_ = false;
  Clock::time_point drawn_at_{};
};

// Reads the identity of the sensor at `found.address` through the family's driver, polled as
// each model of the family (the given one first) until one gets a reading, as `info` does
// (commission/model_detection.h).
boost::asio::awaitable<void> identify(CommissionBus& bus, const SensorConfig& model_sensor,
                                      FoundSensor& found, const bool& stopping) {
  CommissionedSensor sensor{model_sensor, nullptr, ModelSource::detected};
  sensor.config.name = fmt::format("sensor_{}", found.address);
  sensor.config.address = found.address;
  sensor.driver = make_driver(bus.families(), sensor.config, bus.config());
  if (!sensor.driver) co_return;
  const ModelCheck check = co_await check_model(bus, sensor, stopping);
  if (stopping) co_return;
  const SensorState& state = sensor.driver->state();
  found.model = sensor.config.model;
  if (state.identity_known) {
    found.serial = state.serial;
    found.firmware = state.firmware;
    found.lock_level = state.protection_level;
  }
  if (check.outcome().result == PollResult::reading && state.identity_known)
    found.detail.clear();
  else if (!state.identity_known)
    found.detail = "answered the probe, but not the identity read";
  else
    found.detail = fmt::format("identity read, but no measurement ({}): model not known",
                               check.polled_refusal);
}

// A sensor key's value as --config-out writes it. The options' file (--device FILE) reaches the
// stand-in sensor as an absolute path; given relative, it is written relative to the new file's
// folder, where the loader looks for it, so the folder can move or be copied to the gateway
// with its device profiles.
std::string as_written(const std::string& value, const std::string& device_option,
                       const std::string& config_out) {
  namespace fs = std::filesystem;
  if (device_option.empty() || fs::path(device_option).is_absolute() ||
      value != fs::absolute(device_option).string())
    return value;
  const fs::path folder = fs::absolute(config_out).lexically_normal().parent_path();
  return fs::absolute(device_option).lexically_normal().lexically_relative(folder).string();
}

boost::asio::awaitable<int> scan(CommissionBus& bus, const bool& stopping,
                                 const ScanOptions& options, const ScanTarget& target,
                                 const ProtocolEntry& protocol,
                                 const std::vector<std::uint32_t>& addresses,
                                 const std::string& device_option) {
  const ScanDescriptor& scan = protocol.protocol->scan;
  const std::vector<std::uint32_t> bauds =
      scan_bauds(*protocol.protocol, bus.config().baud, options.auto_baud);
  const std::size_t probes_total = options.broadcast ? bauds.size() : addresses.size() * bauds.size();
  Progress progress(::isatty(STDERR_FILENO) && probes_total > kLongScan, options.progress_lines);
  std::vector<FoundSensor> found;
  std::size_t probes = 0;
  const auto started = Clock::now();
  // Found through a gateway the command was not told to use (its control socket serves the
  // tty): it keeps its bus at its rate, so the other rates cannot be tried. Said before any
  // probe rather than after the first rate's.
  if (options.auto_baud && bus.through_gateway() && bauds.size() > 1) {
    std::cerr << fmt::format(
        "tiltgate scan: --baud auto: the running gateway keeps {} at {} baud, and its sensors "
        "are set to it; stop the gateway to try every rate, or scan at its rate without "
        "--baud auto\n",
        bus.config().port, bus.config().baud);
    co_return 1;
  }

  for (const std::uint32_t baud : bauds) {
    if (baud != bus.config().baud) {
      if (auto reopened = bus.reopen_at(baud); !reopened) {
        progress.clear();
        std::cerr << "tiltgate scan: --baud auto: " << reopened.error() << "\n";
        co_return 1;
      }
    }
    ProbeSetup setup;
    setup.master_address = bus.config().master_address;
    setup.timeout = options.probe_timeout_ms
                        ? std::chrono::milliseconds(*options.probe_timeout_ms)
                        : default_probe_timeout(*protocol.protocol, baud);
    if (target.model_sensor) setup.options = target.model_sensor->family_options;
    const std::vector<std::uint32_t> broadcast_only{0};
    const std::size_t found_before = found.size();
    for (const std::uint32_t address : options.broadcast ? broadcast_only : addresses) {
      if (stopping) co_return 0;
      setup.address = address;
      // (Not one conditional expression with two co_awaits: g++ 12 destroys its temporary twice.)
      const ProbeFunction probe = options.broadcast ? scan.ask_address : scan.probe;
      const ProbeResult result = co_await probe(bus.line(), setup);
      ++probes;
      if (result.outcome == ProbeOutcome::failed) {
        progress.clear();
        std::cerr << "tiltgate scan: " << bus.config().port << ": " << result.detail << "\n";
        co_return stopping ? 0 : 1;
      }
      if (result.outcome == ProbeOutcome::answered || result.outcome == ProbeOutcome::garbled) {
        FoundSensor sensor;
        sensor.address = result.address.value_or(address);
        sensor.baud = baud;
        sensor.collision = result.outcome == ProbeOutcome::garbled;
        sensor.detail = result.detail;
        found.push_back(std::move(sensor));
      }
      progress.show(probes, probes_total, baud, found);
    }
    if (target.model_sensor) {
      for (std::size_t i = found_before; i < found.size(); ++i)
        if (!found[i].collision)
          co_await identify(bus, *target.model_sensor, found[i], stopping);
    }
    if (stopping) co_return 0;
  }
  progress.clear();

  const std::vector<RepeatedSensor> repeated = drop_repeated_sensors(found);
  const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - started);
  const bool any = std::any_of(found.begin(), found.end(),
                               [](const FoundSensor& s) { return !s.collision; });
  if (!found.empty()) {
    std::cout << scan_header() << "\n";
    for (const FoundSensor& s : found) std::cout << scan_row(s) << "\n";
  }
  for (const RepeatedSensor& r : repeated) std::cout << repeated_note(r) << "\n";
  std::cout << scan_summary(found, probes, took) << "\n";
  std::cout.flush();

  if (!any) {
    std::cerr << fmt::format(
        "tiltgate scan: no sensor answered on {} ({}, {} baud{})\n"
        "hint: check the baud rate (--baud, or --baud auto to try every rate), the protocol "
        "(--protocol), the wiring (A/B swapped, termination, power) and, for slow devices, "
        "--probe-timeout-ms\n",
        bus.config().port, bus.config().protocol,
        fmt::join(bauds, "/"), options.broadcast ? ", broadcast" : "");
    co_return 1;
  }
  if (!options.config_out.empty()) {
    std::vector<SensorKeyValue> keys;
    for (std::string_view key : required_sensor_keys(*protocol.family))
      keys.push_back({std::string(key),
                      as_written(target.model_sensor->family_options.text(key), device_option,
                                 options.config_out)});
    BusConfig written = bus.config();
    std::ofstream out(options.config_out, std::ios::trunc);
    out << scan_config_text(written, found, keys);
    out.close();
    if (!out) {
      std::cerr << "tiltgate scan: --config-out: cannot write " << options.config_out << "\n";
      co_return 1;
    }
    std::cout << "wrote " << options.config_out << "\n";
  }
  co_return 0;
}

int scan_command(const BusOptions& bus_options, const ScanOptions& options, FamilyList families) {
  auto target = resolve_scan_target(bus_options, options.auto_baud, families);
  if (!target) return report_usage_errors("scan", target.error());
  const ProtocolEntry protocol = find_protocol(families, target->bus.bus.protocol);
  UsageErrors errors;
  auto addresses = scan_addresses(*protocol.protocol, options.from, options.to);
  if (!addresses) errors.push_back(addresses.error());
  if (!bus_options.addresses.empty()) {
    // --address picks the addresses to probe instead of a range.
    if (options.from || options.to) errors.push_back("--address: not with --from or --to");
    addresses = std::vector<std::uint32_t>(bus_options.addresses.begin(),
                                           bus_options.addresses.end());
  }
  if (options.broadcast && !protocol.protocol->scan.ask_address)
    errors.push_back(fmt::format("--broadcast: the {} protocol has no request every sensor "
                                 "answers",
                                 protocol.protocol->name));
  if (options.auto_baud)
    if (auto refused = auto_baud_refusal(*protocol.protocol, target->bus.bus.port))
      errors.push_back(std::move(*refused));
  if (options.auto_baud && bus_options.via_gateway)
    errors.push_back("--baud auto: not with --via-gateway (the running gateway keeps its bus at "
                     "its own rate: stop it to try every rate)");
  if (options.broadcast && (options.from || options.to || !bus_options.addresses.empty()))
    errors.push_back("--broadcast: not with --from, --to or --address (it asks every address)");
  if (!options.config_out.empty()) {
    if (std::filesystem::exists(options.config_out) && !options.force)
      errors.push_back(fmt::format("--config-out: {} exists (--force overwrites it)",
                                   options.config_out));
    if (!target->model_sensor)
      errors.push_back(fmt::format(
          "--config-out: {} sensors need {} in the configuration: give them (e.g. --device "
          "FILE) so that it names them",
          protocol.family->name, fmt::join(required_sensor_keys(*protocol.family), ", ")));
  }
  if (!errors.empty()) return report_usage_errors("scan", errors);

  if (options.broadcast)
    std::cerr << "tiltgate scan: warning: --broadcast works only with one sensor on the bus; "
                 "with several, their replies collide\n";
  CommissionTarget bus = target->bus;
  // A probe that gets no reply costs its time-out plus the quiet the line keeps after it, which
  // keeps a late reply from being taken for the next probe's: the longest probe time-out of the
  // rates to be tried is enough.
  std::chrono::milliseconds guard{0};
  for (const std::uint32_t baud : scan_bauds(*protocol.protocol, bus.bus.baud, options.auto_baud))
    guard = std::max(guard, options.probe_timeout_ms
                                ? std::chrono::milliseconds(*options.probe_timeout_ms)
                                : default_probe_timeout(*protocol.protocol, baud));
  bus.bus.late_guard = guard;
  return run_commissioning_on(
      "scan", bus,
      [&](CommissionBus& commission_bus, const bool& stopping) -> boost::asio::awaitable<int> {
        co_return co_await scan(commission_bus, stopping, options, *target, protocol, *addresses,
                                bus_options.device);
      });
}

}  // namespace

Subcommand add_scan(CLI::App& app, FamilyList families, FamilyCommandsList commands) {
  auto bus = std::make_shared<BusOptions>();
  auto options = std::make_shared<ScanOptions>();
  CLI::App* scan = app.add_subcommand("scan", "find the sensors on a bus: one row per address "
                                              "that answers, and a configuration of them");
  add_bus_options(*scan, *bus, families, &options->auto_baud);
  scan->add_option_function<std::int64_t>(
          "--from", [options](const std::int64_t& v) { options->from = v; },
          "first address to probe (default: the protocol's usual range)")
      ->group("Scan");
  scan->add_option_function<std::int64_t>(
          "--to", [options](const std::int64_t& v) { options->to = v; }, "last address to probe")
      ->group("Scan");
  scan->add_option("--config-out", options->config_out,
                   "write a configuration of the sensors found to this file")
      ->group("Scan");
  scan->add_flag("--force", options->force, "with --config-out: overwrite the file")
      ->group("Scan");
  scan->add_flag("--broadcast", options->broadcast,
                 "ask every sensor at once for its address (one sensor on the bus only)")
      ->group("Scan");
  scan->add_option_function<std::int64_t>(
          "--probe-timeout-ms",
          [options](const std::int64_t& v) { options->probe_timeout_ms = v; },
          "how long to wait for each address (default: the protocol's reply time at the baud "
          "+ 10 ms)")
      ->check(CLI::Range(1, 10'000))
      ->group("Scan");
  // Hidden: for the web console, which runs scan and draws its own bar.
  scan->add_flag("--progress-lines", options->progress_lines)->group("");
  scan->footer(scan_help_footer(commands));
  return {scan, [bus, options, families] { return scan_command(*bus, *options, families); },
          true};
}

}  // namespace tiltgate
