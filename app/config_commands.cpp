// `check`, `map` and `run`: the subcommands that start from a configuration file.
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <deque>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <vector>

#include "config/config_loader.h"
#include "config/machine_checks.h"
#include "config/redundancy_warnings.h"
#include "monitoring/record_budget.h"
#include "app/config_commands.h"
#include "app/config_reload.h"
#include "app/served_gateway.h"
#include "app/run_as_user.h"
#include "app/service_notify.h"
#include "driver/visible_text.h"
#include "line_scheduling/line_budget.h"
#include "mapping/aggregate_layout.h"

namespace tiltgate {

namespace {

// What a command asks of a configuration: valid, or valid and servable here (check, run).
enum class Checked { file, on_this_machine };

// Loads and validates; prints every problem to stderr, compiler style.
std::optional<Config> load_or_report(const std::string& path, FamilyList families,
                                     Checked checked) {
  auto loaded = load_config_file(path, families);
  if (checked == Checked::on_this_machine) loaded = checked_on_this_machine(std::move(loaded));
  if (!loaded) {
    // Under systemd stderr is the journal: a value quoted in an error is shown escaped there.
    for (const ConfigError& error : loaded.error())
      std::cerr << visible_text(error.to_string()) << "\n";
    std::cerr << fmt::format("{}: {} error(s); nothing started\n", visible_text(path),
                             loaded.error().size());
    return std::nullopt;
  }
  return std::move(*loaded);
}

// The TCP port of a listener (config.h, listener_of).
std::uint16_t served_port(const Config& config, std::uint16_t listener) {
  return listener == kMainListener ? config.server.port : listener;
}

// An aggregate's layout as a unit of `tiltgate map`: each sensor's points at their place in
// its block ("SENSOR.POINT"), and where each block starts. `units` holds the sensors' maps.
std::optional<UnitMap> aggregate_unit(const Config& config, const AggregateConfig& aggregate,
                                      const std::vector<UnitMap>& units,
                                      std::deque<RegisterMap>& maps) {
  std::vector<AggregateMember> members;
  for (const std::string& name : aggregate.sensors)
    for (std::size_t i = 0; i < config.sensors.size(); ++i)
      if (config.sensors[i].name == name) members.push_back({name, units[i].map});
  auto layout = make_aggregate_layout(aggregate.points, members);
  if (!layout) return std::nullopt;  // the loader reports it
  std::vector<std::string> starts;
  for (std::size_t i = 0; i < members.size(); ++i)
    starts.push_back(fmt::format("{} at {}", members[i].name, layout->block_start(i)));
  maps.push_back(aggregate_register_map(*layout, members));
  return UnitMap{aggregate.unit_id,
                 fmt::format("aggregate of {} sensor(s)", members.size()),
                 "aggregate",
                 &maps.back(),
                 config.server.word_order,
                 served_port(config, listener_of(config, aggregate)),
                 fmt::format("Blocks of {} registers ({}), read alike as input (FC4) or holding "
                             "(FC3) registers; writes are refused. Blocks start at: {}.",
                             layout->block_words, fmt::join(aggregate.points, ", "),
                             fmt::join(starts, ", "))};
}

int check_command(const std::string& config_path, FamilyList families) {
  auto config = load_or_report(config_path, families, Checked::on_this_machine);
  if (!config) return 1;
  // Not errors: the file is valid and runs; the line's settings may not keep its promise, nor
  // a standby hear every line.
  std::vector<std::string> warnings = line_budget_warnings(*config, families);
  for (std::string& warning : redundancy_warnings(*config, families))
    warnings.push_back(std::move(warning));
  for (const std::string& warning : warnings)
    std::cerr << fmt::format("{}: warning: {}\n", visible_text(config_path), visible_text(warning));
  std::cout << fmt::format("{}: OK ({} bus(es), {} sensor(s){})\n", config_path,
                           config->buses.size(), config->sensors.size(),
                           config->aggregates.empty()
                               ? std::string()
                               : fmt::format(", {} aggregate(s)", config->aggregates.size()));
  // The disk the long record will take ([record], docs/monitoring.md "The long record").
  std::cout << fmt::format("{}: {}\n", config_path,
                           monitoring::record_budget_text(
                               config->sensors.size(), config->record.keep_days,
                               std::uint32_t(config->record.interval.count())));
  return 0;
}

int map_command(const std::string& config_path, const std::string& format, FamilyList families) {
  auto config = load_or_report(config_path, families, Checked::file);
  if (!config) return 1;
  // A deque: the units point into it as it grows.
  std::deque<RegisterMap> maps;
  std::vector<UnitMap> units;
  for (const SensorConfig& sensor : config->sensors) {
    maps.push_back(map_for(families, sensor));
    units.push_back({sensor.unit_id, sensor.name, sensor.model, &maps.back(),
                     config->server.word_order, served_port(*config, listener_of(*config, sensor)), {}});
  }
  for (const AggregateConfig& aggregate : config->aggregates) {
    if (auto unit = aggregate_unit(*config, aggregate, units, maps)) units.push_back(*unit);
  }
  std::cout << (format == "markdown" ? export_markdown(units) : export_csv(units));
  return 0;
}

// The folders the serving user will write in but may not be able to make (in /run, /var/lib),
// made for it while still root.
std::vector<std::filesystem::path> folders_written(const Config& config) {
  std::vector<std::filesystem::path> folders;
  if (!config.server.control_socket.empty())
    folders.push_back(std::filesystem::path(config.server.control_socket).parent_path());
  if (config.mqtt.enabled && !config.mqtt.state_dir.empty())
    folders.emplace_back(config.mqtt.state_dir);
  if (config.sparkplug.enabled) folders.emplace_back(config.sparkplug.state_dir);
  if (!config.server.state_dir.empty()) folders.emplace_back(config.server.state_dir);
  return folders;
}

Expected<Done, std::string> switch_to_serving_user(const Config& config) {
  auto user = find_user(config.server.user);
  if (!user) return Unexpected{user.error()};
  if (geteuid() == 0 && user->uid != 0)
    for (const std::string& error : make_folders_for(*user, folders_written(config)))
      spdlog::error("{}", visible_text(error));
  return run_as_user(*user);
}

int run_command(const std::string& config_path, FamilyList families) {
  // A console apply left unconfirmed while no gateway ran: the previous file, before loading.
  const std::optional<PendingApply> rolled_back = ConfirmWindow::roll_back_if_due(config_path);
  auto config = load_or_report(config_path, families, Checked::on_this_machine);
  if (!config) {
    ConfirmWindow::roll_back_failed_start(config_path);
    return 1;
  }
  boost::asio::io_context io;
  // Before start(): a SIGHUP from then on reloads rather than ends the process.
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  boost::asio::signal_set hangups(io, SIGHUP);
  ServedGateway served(io, *config, families);
  Gateway& gateway = served.gateway();
  // An applied configuration that cannot start is not kept for the next start.
  const auto give_up = [&](const std::string& why) {
    spdlog::critical("{}", visible_text(why));
    ConfirmWindow::roll_back_failed_start(config_path);
    return 1;
  };
  auto started = gateway.start();
  if (!started) return give_up(started.error());
  // The ttys and listeners are open: root is no longer needed.
  if (!config->server.user.empty()) {
    if (auto switched = switch_to_serving_user(*config); !switched)
      return give_up(switched.error());
    spdlog::info("serving as user {} (uid {})", visible_text(config->server.user), getuid());
  } else if (geteuid() == 0) {
    spdlog::warn("running as root: set [server] user to serve unprivileged once started "
                 "(docs/operations.md, \"Running without root\")");
  }
  // Only now the services that write files: the stores and the control socket are the
  // serving user's, and it can replace them at a reload.
  served.start_as_user();
  served.confirm_window().resume(rolled_back);
  // Listeners bound, ttys opened, privileges dropped: systemd may now count the service as up.
  ServiceNotifier notifier(io);
  notifier.ready();
  signals.async_wait([&](const boost::system::error_code& ec, int signal) {
    if (ec) return;
    spdlog::info("signal {}: shutting down", signal);
    notifier.stopping();
    hangups.cancel();
    gateway.stop();
    io.stop();
  });
  reload_on_sighup(hangups, gateway, config_path, families, notifier);
  io.run();
  finish_stopped(io);
  return 0;
}

}  // namespace

Subcommand add_run(CLI::App& app, FamilyList families) {
  auto config_path = std::make_shared<std::string>();
  CLI::App* run = app.add_subcommand("run", "serve the sensors of a configuration file");
  run->footer(
      "SIGHUP (systemctl reload tiltgate) re-reads the configuration file: a valid one applies "
      "without dropping connected Modbus clients or queued writes (unchanged buses and sensors "
      "are kept as they are); an invalid one is refused, its errors logged, and the running "
      "configuration keeps serving. SIGINT or SIGTERM stops.");
  run->add_option("-c,--config", *config_path, "configuration file")->required();
  return {run, [config_path, families] { return run_command(*config_path, families); }};
}

Subcommand add_check(CLI::App& app, FamilyList families) {
  auto config_path = std::make_shared<std::string>();
  CLI::App* check = app.add_subcommand("check", "validate a configuration file; exit 0 or 1");
  check->add_option("-c,--config", *config_path, "configuration file")->required();
  return {check, [config_path, families] { return check_command(*config_path, families); }};
}

Subcommand add_map(CLI::App& app, FamilyList families) {
  auto config_path = std::make_shared<std::string>();
  auto format = std::make_shared<std::string>("csv");
  CLI::App* map = app.add_subcommand("map", "print the register map of every configured sensor");
  map->add_option("-c,--config", *config_path, "configuration file")->required();
  map->add_option("--format", *format, "csv or markdown")
      ->check(CLI::IsMember({"csv", "markdown"}))
      ->capture_default_str();
  return {map,
          [config_path, format, families] { return map_command(*config_path, *format, families); }};
}

}  // namespace tiltgate
