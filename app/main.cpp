// tiltgate: Modbus/TCP gateway for RS485 inclinometers.
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <string>
#include <vector>

#include "commission/commands.h"
#include "commission/commission_cli.h"
#include "app/journal_log.h"

namespace {

void set_up_logging(const std::string& level) {
  auto logger = spdlog::stderr_color_mt("tiltgate");
  spdlog::set_default_logger(logger);
  // Under systemd, stderr is the journal: it keeps the time, and takes the priority from a
  // "<4>" prefix (journal_log.h).
  if (tiltgate::stderr_is_journal())
    spdlog::set_formatter(tiltgate::journal_formatter());
  else
    spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %^%-5l%$ %v");
  spdlog::set_level(spdlog::level::from_str(level));
}

// "A, B and C": the families' titles.
std::string family_titles(tiltgate::FamilyCommandsList families) {
  std::string titles;
  for (std::size_t i = 0; i < families.size(); ++i) {
    if (i > 0) titles += i + 1 == families.size() ? " and " : ", ";
    titles += families[i]->title;
  }
  return titles;
}

}  // namespace

int main(int argc, char** argv) {
  // The sensor families this build serves: asked for here, once, and handed to every command;
  // what the gateway runs of them, and what the command line shows and runs.
  const tiltgate::FamilyList families = tiltgate::registered_families();
  const tiltgate::FamilyCommandsList commands = tiltgate::registered_family_commands();
  CLI::App app{"tiltgate: Modbus/TCP gateway for " + family_titles(commands) + " inclinometers"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tiltgate ") + TILTGATE_VERSION);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();

  std::string config_path;
  auto* run = app.add_subcommand("run", "serve the sensors of a configuration file");
  run->footer(
      "SIGHUP (systemctl reload tiltgate) re-reads the configuration file: a valid one applies "
      "without dropping connected Modbus clients or queued writes (unchanged buses and sensors "
      "are kept as they are); an invalid one is refused, its errors logged, and the running "
      "configuration keeps serving. SIGINT or SIGTERM stops.");
  run->add_option("-c,--config", config_path, "configuration file")->required();
  auto* check = app.add_subcommand("check", "validate a configuration file; exit 0 or 1");
  check->add_option("-c,--config", config_path, "configuration file")->required();
  std::string format = "csv";
  auto* map = app.add_subcommand("map", "print the register map of every configured sensor");
  map->add_option("-c,--config", config_path, "configuration file")->required();
  map->add_option("--format", format, "csv or markdown")
      ->check(CLI::IsMember({"csv", "markdown"}))
      ->capture_default_str();

  tiltgate::DemoOptions demo_options;
  auto* demo = app.add_subcommand("demo", "serve built-in simulated sensors (writes enabled)");
  demo->add_option("--listen", demo_options.listen, "address to bind")->capture_default_str();
  demo->add_option("--port", demo_options.port, "Modbus TCP port")->capture_default_str();
  demo->add_option("--http-port", demo_options.http_port,
                   "HTTP status API and metrics port (0: off)")
      ->capture_default_str();
  demo->add_option("--mqtt-host", demo_options.mqtt_host,
                   "MQTT broker to publish the sensors to, under tiltgate/demo/ (default: off)");
  demo->add_option("--mqtt-port", demo_options.mqtt_port, "MQTT broker port")
      ->capture_default_str();

  // Commissioning: the vendor's Windows apps, from an SSH session.
  tiltgate::BusOptions info_bus;
  auto* info = app.add_subcommand("info", "show a sensor's address, model, serial, firmware, "
                                          "lock level and angles (the User App's Sensor Info)");
  tiltgate::add_bus_options(*info, info_bus, families);
  info->footer(tiltgate::info_help_footer(commands));

  tiltgate::BusOptions watch_bus;
  tiltgate::WatchOptions watch_options;
  auto* watch = app.add_subcommand("watch", "poll sensors in turn and show their angles, one "
                                            "row each (the Multi-Unit Angle Display)");
  tiltgate::add_bus_options(*watch, watch_bus, families);
  watch->add_option("--count", watch_options.count, "stop after this many rounds (plain lines)")
      ->check(CLI::Range(1, 100'000'000));
  watch->add_option("--interval", watch_options.interval_ms, "ms from one round to the next")
      ->check(CLI::Range(10, 3'600'000))
      ->capture_default_str();
  watch->add_option("--log", watch_options.log,
                    "append every reading to this CSV file (time, address, serial, x_deg, "
                    "y_deg, tilt_deg, status)");
  watch->footer(tiltgate::watch_help_footer(commands));

  tiltgate::BusOptions scan_bus;
  tiltgate::ScanOptions scan_options;
  auto* scan = app.add_subcommand("scan", "find the sensors on a bus: one row per address that "
                                          "answers, and a configuration of them");
  tiltgate::add_bus_options(*scan, scan_bus, families, &scan_options.auto_baud);
  scan->add_option_function<std::int64_t>(
          "--from", [&](const std::int64_t& v) { scan_options.from = v; },
          "first address to probe (default: the protocol's usual range)")
      ->group("Scan");
  scan->add_option_function<std::int64_t>(
          "--to", [&](const std::int64_t& v) { scan_options.to = v; }, "last address to probe")
      ->group("Scan");
  scan->add_option("--config-out", scan_options.config_out,
                   "write a configuration of the sensors found to this file")
      ->group("Scan");
  scan->add_flag("--force", scan_options.force, "with --config-out: overwrite the file")
      ->group("Scan");
  scan->add_flag("--broadcast", scan_options.broadcast,
                 "ask every sensor at once for its address (one sensor on the bus only)")
      ->group("Scan");
  scan->add_option_function<std::int64_t>(
          "--probe-timeout-ms", [&](const std::int64_t& v) { scan_options.probe_timeout_ms = v; },
          "how long to wait for each address (default: the protocol's reply time at the baud "
          "+ 10 ms)")
      ->check(CLI::Range(1, 10'000))
      ->group("Scan");
  scan->footer(tiltgate::scan_help_footer(commands));

  tiltgate::BusOptions set_bus;
  tiltgate::SetArguments set_arguments;
  auto* set = app.add_subcommand("set", "change one setting of a sensor (address, baud, filter, "
                                        "zero, restart, the model's own) and read it back");
  tiltgate::add_bus_options(*set, set_bus, families);
  // One address, so that the SETTING words after it are not taken for more addresses.
  set->get_option("--address")->allow_extra_args(false);
  set->add_option("setting", set_arguments.words, "SETTING [VALUE...]")->required();
  set->add_flag("--permanent", set_arguments.permanent, "zero-here: keep the zero after a restart");
  set->footer(tiltgate::set_help_footer(commands));

  tiltgate::BusOptions raw_bus;
  tiltgate::RawOptions raw_options;
  auto* raw = app.add_subcommand("raw", "send one request by function number and show the bytes "
                                        "each way and the reply (the User App's command section)");
  tiltgate::add_bus_options(*raw, raw_bus, families);
  raw->get_option("--address")->allow_extra_args(false);
  raw->add_option("--function", raw_options.function, "the function / command number (see below)")
      ->required();
  raw->add_option("--data", raw_options.data, "the request's data bytes in hex, e.g. \"00 10\"");
  raw->footer(tiltgate::raw_help_footer(commands));

  auto* sim = app.add_subcommand("sim", "run a simulated sensor bus on a pseudo-terminal");
  sim->require_subcommand(1);
  // One `sim` subcommand per family.
  std::vector<tiltgate::SimulatorSetup> sim_setups(commands.size());
  std::vector<std::string> sim_protocols(commands.size());
  std::vector<CLI::App*> sim_commands;
  for (std::size_t i = 0; i < commands.size(); ++i) {
    const tiltgate::SimulatorDescriptor& simulator = commands[i]->simulator;
    const tiltgate::FamilyDescriptor& family = *commands[i]->family;
    tiltgate::SimulatorSetup& setup = sim_setups[i];
    auto* command = sim->add_subcommand(std::string(simulator.command), std::string(simulator.help));
    // A family of several protocols chooses one by its short name, the first by default.
    const std::vector<std::string> choices = tiltgate::simulator_protocol_choices(family);
    if (!choices.empty()) {
      sim_protocols[i] = choices.front();
      command
          ->add_option("--protocol", sim_protocols[i], tiltgate::simulator_protocols_help(family))
          ->check(CLI::IsMember(choices))
          ->capture_default_str();
    }
    setup.sensors = simulator.default_sensors;
    command->add_option("--sensors", setup.sensors, std::string(simulator.sensors_help))
        ->capture_default_str();
    command->add_option("--link", setup.link, "also make this symlink to the pty");
    command->add_option("--pace-baud", setup.pace_baud,
                        "pace replies at this baud rate (0: no pacing)");
    command->add_option("--baud", setup.listen_baud,
                        "answer only requests sent at this baud rate, as sensors set to it do "
                        "(0: any rate)");
    command->add_flag("--shared-addresses", setup.shared_addresses,
                      "let sensors share an address, as on a bus commissioned by mistake: "
                      "their replies collide and arrive garbled");
    sim_commands.push_back(command);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every other parse error is a usage error, exit 2.
    return app.exit(e) == 0 ? 0 : 2;
  }
  // A commissioning command's own output is the point: the drivers' warnings about a silent
  // sensor would only repeat it (and break the redrawn table), unless asked for.
  const bool commissioning = *info || *watch || *scan || *set || *raw;
  if (commissioning && app.get_option("--log-level")->count() == 0) log_level = "error";
  set_up_logging(log_level);

  if (*run) return tiltgate::run_command(config_path, families);
  if (*check) return tiltgate::check_command(config_path, families);
  if (*map) return tiltgate::map_command(config_path, format, families);
  if (*demo) return tiltgate::demo_command(demo_options, commands);
  if (*info) return tiltgate::info_command(info_bus, families);
  if (*watch) return tiltgate::watch_command(watch_bus, watch_options, families);
  if (*scan) return tiltgate::scan_command(scan_bus, scan_options, families);
  if (*set) return tiltgate::set_command(set_bus, set_arguments, families, commands);
  if (*raw) return tiltgate::raw_command(raw_bus, raw_options, families, commands);
  for (std::size_t i = 0; i < commands.size(); ++i) {
    if (!*sim_commands[i]) continue;
    sim_setups[i].protocol = tiltgate::protocol_of_choice(*commands[i]->family, sim_protocols[i]);
    return tiltgate::sim_command(*commands[i], sim_setups[i]);
  }
  return 2;
}
