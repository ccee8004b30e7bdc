// `tiltgate scan` on the command line: the engine's scan (commission/scan_engine.h) shown as
// text: a progress bar on a terminal, a table of what answered, and a configuration of the
// sensors found written with --config-out.
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <iostream>
#include <unistd.h>

#include "commission_cli/commands.h"
#include "commission_cli/commission_run.h"
#include "commission/event_text.h"
#include "commission/scan_engine.h"

namespace tiltgate {

namespace {

// Scans of more probes than this show a progress bar on a terminal.
constexpr std::size_t kLongScan = 64;
constexpr std::chrono::milliseconds kRedrawEvery{100};

using Clock = std::chrono::steady_clock;

// Shows how far the scan is, redrawn in place on stderr; nothing when not a terminal.
class Progress {
 public:
  explicit Progress(bool shown) : shown_(shown) {}
  ~Progress() { clear(); }
  void show(std::size_t done, std::size_t total, std::uint32_t baud,
            const std::vector<FoundSensor>& found) {
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
  bool drawn_ = false;
  Clock::time_point drawn_at_{};
};

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

// The scan's events as the command line shows them: progress on stderr, the table and its
// summary on stdout, failures as "tiltgate scan: ..." on stderr.
class ScanText {
 public:
  explicit ScanText(bool bar) : progress_(bar) {}

  void operator()(const CommissionEvent& event) {
    if (const auto* progress = std::get_if<ProgressEvent>(&event)) {
      progress_.show(progress->done, progress->total, progress->baud, progress->found);
    } else if (const auto* note = std::get_if<NoteEvent>(&event)) {
      progress_.clear();
      std::cerr << "tiltgate scan: " << (note->warning ? "warning: " : "") << note->text << "\n";
    } else if (const auto* failed = std::get_if<FailedEvent>(&event)) {
      progress_.clear();
      std::cerr << "tiltgate scan: " << failed->message << "\n";
    } else if (const auto* finished = std::get_if<ScanFinishedEvent>(&event)) {
      progress_.clear();
      std::cout << scan_result_text(*finished) << std::flush;
      configuration_ = finished->configuration;
    }
  }
  // The configuration of the sensors found, once the scan finished.
  const std::string& configuration() const { return configuration_; }

 private:
  Progress progress_;
  std::string configuration_;
};

// What --config-out and --force add to the engine's checks.
UsageErrors config_out_errors(const ScanOptions& options, const PreparedScan& scan) {
  UsageErrors errors;
  if (options.config_out.empty()) return errors;
  if (std::filesystem::exists(options.config_out) && !options.force)
    errors.push_back(fmt::format("--config-out: {} exists (--force overwrites it)",
                                 options.config_out));
  if (!scan.model_sensor)
    errors.push_back(fmt::format(
        "--config-out: {} sensors need {} in the configuration: give them (e.g. --device "
        "FILE) so that it names them",
        scan.protocol.family->name, fmt::join(required_sensor_keys(*scan.protocol.family), ", ")));
  return errors;
}

int write_config_out(const std::string& path, const std::string& configuration) {
  std::ofstream out(path, std::ios::trunc);
  out << configuration;
  out.close();
  if (!out) {
    std::cerr << "tiltgate scan: --config-out: cannot write " << path << "\n";
    return 1;
  }
  std::cout << "wrote " << path << "\n";
  return 0;
}

// A scan run by a gateway names the options' file as the gateway read it, by its absolute
// path: the configuration and tables say it as a scan of the command's own does (as_written).
CommissionEvent written_as_here(CommissionEvent event, const std::string& device_option,
                                const std::string& config_out) {
  auto* finished = std::get_if<ScanFinishedEvent>(&event);
  if (finished == nullptr || device_option.empty()) return event;
  const std::string absolute = std::filesystem::absolute(device_option).string();
  const std::string written = as_written(absolute, device_option, config_out);
  if (written == absolute) return event;
  const auto replace_all = [&](std::string& text) {
    const std::string from = toml_string(absolute);
    const std::string to = toml_string(written);
    for (std::size_t at = text.find(from); at != std::string::npos;
         at = text.find(from, at + to.size()))
      text.replace(at, from.size(), to);
  };
  replace_all(finished->configuration);
  for (SensorTable& table : finished->tables) replace_all(table.text);
  return event;
}

int scan_command(const BusOptions& bus_options, const ScanOptions& options, FamilyList families) {
  auto scan = prepare_scan(bus_options, options, families);
  if (!scan) return report_usage_errors("scan", scan.error());
  if (UsageErrors errors = config_out_errors(options, *scan); !errors.empty())
    return report_usage_errors("scan", errors);
  for (SensorKeyValue& key : scan->sensor_keys)
    key.value = as_written(key.value, bus_options.device, options.config_out);
  const std::size_t probes =
      (scan->broadcast ? 1 : scan->addresses.size()) *
      scan_bauds(*scan->protocol.protocol, scan->bus.bus.baud, scan->auto_baud).size();
  ScanText text(::isatty(STDERR_FILENO) && probes > kLongScan);
  const EventSink report = [&text](const CommissionEvent& event) { text(event); };
  const EventSink through_gateway = [&](const CommissionEvent& event) {
    text(written_as_here(event, bus_options.device, options.config_out));
  };
  const int exit_code = run_commissioning_on(
      "scan", scan->bus,
      [&](CommissionBus& bus, const bool& stopping) -> boost::asio::awaitable<int> {
        co_return co_await scan_bus(bus, *scan, report, stopping);
      },
      GatewayRequest{CommandRequest{"scan", bus_options, options, {}, {}, {}},
                     through_gateway, nullptr});
  if (exit_code != 0 || options.config_out.empty() || text.configuration().empty())
    return exit_code;
  return write_config_out(options.config_out, text.configuration());
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
  scan->footer(scan_help_footer(commands));
  return {scan, [bus, options, families] { return scan_command(*bus, *options, families); },
          true};
}

}  // namespace tiltgate
