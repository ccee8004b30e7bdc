// tiltgate: Modbus/TCP gateway for RS485 inclinometers.
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <string>
#include <vector>

#include "gateway/commands.h"

namespace {

void set_up_logging(const std::string& level) {
  auto logger = spdlog::stderr_color_mt("tiltgate");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %^%-5l%$ %v");
  spdlog::set_level(spdlog::level::from_str(level));
}

// "A, B and C": the families' titles.
std::string family_titles() {
  const tiltgate::FamilyList families = tiltgate::registered_families();
  std::string titles;
  for (std::size_t i = 0; i < families.size(); ++i) {
    if (i > 0) titles += i + 1 == families.size() ? " and " : ", ";
    titles += families[i]->title;
  }
  return titles;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tiltgate: Modbus/TCP gateway for " + family_titles() + " inclinometers"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tiltgate ") + TILTGATE_VERSION);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();

  std::string config_path;
  auto* run = app.add_subcommand("run", "serve the sensors of a configuration file");
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

  auto* sim = app.add_subcommand("sim", "run a simulated sensor bus on a pseudo-terminal");
  sim->require_subcommand(1);
  // One `sim` subcommand per family.
  const tiltgate::FamilyList families = tiltgate::registered_families();
  std::vector<tiltgate::SimulatorSetup> sim_setups(families.size());
  std::vector<CLI::App*> sim_commands;
  for (std::size_t i = 0; i < families.size(); ++i) {
    const tiltgate::SimulatorDescriptor& simulator = families[i]->simulator;
    tiltgate::SimulatorSetup& setup = sim_setups[i];
    auto* command = sim->add_subcommand(std::string(simulator.command), std::string(simulator.help));
    if (!simulator.protocols.empty()) {
      setup.protocol = simulator.protocols.front();
      const std::vector<std::string> choices(simulator.protocols.begin(), simulator.protocols.end());
      command->add_option("--protocol", setup.protocol, std::string(simulator.protocols_help))
          ->check(CLI::IsMember(choices))
          ->capture_default_str();
    }
    setup.sensors = simulator.default_sensors;
    command->add_option("--sensors", setup.sensors, std::string(simulator.sensors_help))
        ->capture_default_str();
    command->add_option("--link", setup.link, "also make this symlink to the pty");
    command->add_option("--pace-baud", setup.pace_baud,
                        "pace replies at this baud rate (0: no pacing)");
    sim_commands.push_back(command);
  }

  CLI11_PARSE(app, argc, argv);
  set_up_logging(log_level);

  if (*run) return tiltgate::run_command(config_path);
  if (*check) return tiltgate::check_command(config_path);
  if (*map) return tiltgate::map_command(config_path, format);
  if (*demo) return tiltgate::demo_command(demo_options);
  for (std::size_t i = 0; i < families.size(); ++i)
    if (*sim_commands[i]) return tiltgate::sim_command(*families[i], sim_setups[i]);
  return 2;
}
