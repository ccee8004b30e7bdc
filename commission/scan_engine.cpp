#include "commission/scan_engine.h"

#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commission/model_detection.h"
#include "gateway/driver_registry.h"

namespace tiltgate {

namespace {

using Clock = std::chrono::steady_clock;

// A command-line bus gets a stand-in sensor so that --model and the family's keys (--device)
// are read and checked as for any sensor; a family whose sensors need a key the options do not
// give is scanned without one.
Expected<PreparedScan, UsageErrors> resolve_scan_target(BusOptions options, bool auto_baud,
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
        PreparedScan out;
        out.bus = *target;
        out.model_sensor = target->sensors.front();
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
  PreparedScan out;
  out.bus = *target;
  if (!out.bus.sensors.empty()) out.model_sensor = out.bus.sensors.front();
  return out;
}

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

// The checks of the options against each other and the protocol; each error names its option.
UsageErrors scan_option_errors(const BusOptions& bus_options, const ScanOptions& options,
                               PreparedScan& scan) {
  const ProtocolDescriptor& protocol = *scan.protocol.protocol;
  UsageErrors errors;
  auto addresses = scan_addresses(protocol, options.from, options.to);
  if (!addresses) errors.push_back(addresses.error());
  if (!bus_options.addresses.empty()) {
    // --address picks the addresses to probe instead of a range.
    if (options.from || options.to) errors.push_back("--address: not with --from or --to");
    addresses = std::vector<std::uint32_t>(bus_options.addresses.begin(),
                                           bus_options.addresses.end());
  }
  if (addresses) scan.addresses = std::move(*addresses);
  if (options.broadcast && !protocol.scan.ask_address)
    errors.push_back(fmt::format("--broadcast: the {} protocol has no request every sensor "
                                 "answers",
                                 protocol.name));
  if (options.auto_baud)
    if (auto refused = auto_baud_refusal(protocol, scan.bus.bus.port))
      errors.push_back(std::move(*refused));
  if (options.auto_baud && bus_options.via_gateway)
    errors.push_back("--baud auto: not with --via-gateway (the running gateway keeps its bus at "
                     "its own rate: stop it to try every rate)");
  if (options.broadcast && (options.from || options.to || !bus_options.addresses.empty()))
    errors.push_back("--broadcast: not with --from, --to or --address (it asks every address)");
  return errors;
}

// One rate's probes; false when the bus failed (a FailedEvent said so) or the scan stopped.
boost::asio::awaitable<bool> probe_at(CommissionBus& bus, const PreparedScan& scan,
                                      std::uint32_t baud, std::size_t probes_total,
                                      std::size_t& probes, std::vector<FoundSensor>& found,
                                      const EventSink& report, const bool& stopping) {
  const ScanDescriptor& descriptor = scan.protocol.protocol->scan;
  ProbeSetup setup;
  setup.master_address = bus.config().master_address;
  setup.timeout = scan.probe_timeout_ms ? std::chrono::milliseconds(*scan.probe_timeout_ms)
                                        : default_probe_timeout(*scan.protocol.protocol, baud);
  if (scan.model_sensor) setup.options = scan.model_sensor->family_options;
  const std::vector<std::uint32_t> broadcast_only{0};
  for (const std::uint32_t address : scan.broadcast ? broadcast_only : scan.addresses) {
    if (stopping) co_return false;
    setup.address = address;
    // (Not one conditional expression with two co_awaits: g++ 12 destroys its temporary twice.)
    const ProbeFunction probe = scan.broadcast ? descriptor.ask_address : descriptor.probe;
    const ProbeResult result = co_await probe(bus.line(), setup);
    ++probes;
    if (result.outcome == ProbeOutcome::failed) {
      if (!stopping)
        report(FailedEvent{1, fmt::format("{}: {}", bus.config().port, result.detail)});
      co_return false;
    }
    if (result.outcome == ProbeOutcome::answered || result.outcome == ProbeOutcome::garbled) {
      FoundSensor sensor;
      sensor.address = result.address.value_or(address);
      sensor.baud = baud;
      sensor.collision = result.outcome == ProbeOutcome::garbled;
      sensor.detail = result.detail;
      found.push_back(std::move(sensor));
    }
    report(ProgressEvent{probes, probes_total, baud, found});
  }
  co_return true;
}

}  // namespace

Expected<PreparedScan, UsageErrors> prepare_scan(BusOptions bus_options,
                                                 const ScanOptions& options, FamilyList families) {
  auto scan = resolve_scan_target(bus_options, options.auto_baud, families);
  if (!scan) return Unexpected{scan.error()};
  scan->protocol = find_protocol(families, scan->bus.bus.protocol);
  scan->auto_baud = options.auto_baud;
  scan->broadcast = options.broadcast;
  scan->probe_timeout_ms = options.probe_timeout_ms;
  if (UsageErrors errors = scan_option_errors(bus_options, options, *scan); !errors.empty())
    return Unexpected{std::move(errors)};
  if (scan->model_sensor)
    for (std::string_view key : required_sensor_keys(*scan->protocol.family))
      scan->sensor_keys.push_back(
          {std::string(key), scan->model_sensor->family_options.text(key)});
  // A probe that gets no reply costs its time-out plus the quiet the line keeps after it, which
  // keeps a late reply from being taken for the next probe's: the longest probe time-out of the
  // rates to be tried is enough.
  std::chrono::milliseconds guard{0};
  for (const std::uint32_t baud :
       scan_bauds(*scan->protocol.protocol, scan->bus.bus.baud, options.auto_baud))
    guard = std::max(guard, options.probe_timeout_ms
                                ? std::chrono::milliseconds(*options.probe_timeout_ms)
                                : default_probe_timeout(*scan->protocol.protocol, baud));
  scan->bus.bus.late_guard = guard;
  return scan;
}

boost::asio::awaitable<int> scan_bus(CommissionBus& bus, const PreparedScan& scan,
                                     const EventSink& report, const bool& stopping) {
  const ProtocolDescriptor& protocol = *scan.protocol.protocol;
  const std::vector<std::uint32_t> bauds = scan_bauds(protocol, bus.config().baud, scan.auto_baud);
  const std::size_t probes_total = scan.broadcast ? bauds.size() : scan.addresses.size() * bauds.size();
  if (scan.broadcast)
    report(NoteEvent{true, "--broadcast works only with one sensor on the bus; with several, "
                           "their replies collide"});
  // Found through a gateway the command was not told to use (its control socket serves the
  // tty): it keeps its bus at its rate, so the other rates cannot be tried. Said before any
  // probe rather than after the first rate's.
  if (scan.auto_baud && bus.through_gateway() && bauds.size() > 1) {
    report(FailedEvent{
        1, fmt::format("--baud auto: the running gateway keeps {} at {} baud, and its sensors "
                       "are set to it; stop the gateway to try every rate, or scan at its rate "
                       "without --baud auto",
                       bus.config().port, bus.config().baud)});
    co_return 1;
  }
  std::vector<FoundSensor> found;
  std::size_t probes = 0;
  const auto started = Clock::now();
  for (const std::uint32_t baud : bauds) {
    if (baud != bus.config().baud) {
      if (auto reopened = bus.reopen_at(baud); !reopened) {
        report(FailedEvent{1, "--baud auto: " + reopened.error()});
        co_return 1;
      }
    }
    const std::size_t found_before = found.size();
    if (!co_await probe_at(bus, scan, baud, probes_total, probes, found, report, stopping))
      co_return stopping ? 0 : 1;
    if (scan.model_sensor) {
      for (std::size_t i = found_before; i < found.size(); ++i)
        if (!found[i].collision) co_await identify(bus, *scan.model_sensor, found[i], stopping);
    }
    if (stopping) co_return 0;
  }

  ScanFinishedEvent finished;
  finished.repeated = drop_repeated_sensors(found);
  for (const FoundSensor& sensor : found) report(DeviceFoundEvent{sensor});
  finished.took = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - started);
  finished.probes = probes;
  finished.configuration =
      scan_config_text(bus.config(), found, scan.sensor_keys, scan.bus.configured);
  finished.tables = sensor_tables(bus.config(), found, scan.sensor_keys, scan.bus.configured);
  finished.found = std::move(found);
  const bool any = std::any_of(finished.found.begin(), finished.found.end(),
                               [](const FoundSensor& s) { return !s.collision; });
  report(finished);
  if (!any) {
    report(FailedEvent{
        1, fmt::format(
               "no sensor answered on {} ({}, {} baud{})\n"
               "hint: check the baud rate (--baud, or --baud auto to try every rate), the "
               "protocol (--protocol), the wiring (A/B swapped, termination, power) and, for "
               "slow devices, --probe-timeout-ms",
               bus.config().port, bus.config().protocol, fmt::join(bauds, "/"),
               scan.broadcast ? ", broadcast" : "")});
    co_return 1;
  }
  co_return 0;
}

}  // namespace tiltgate
