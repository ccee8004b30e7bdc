// tiltgate: Modbus/TCP gateway for RS485 inclinometers.
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "gateway/commands.h"

namespace {

void set_up_logging(const std::string& level) {
  auto logger = spdlog::stderr_color_mt("tiltgate");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %^%-5l%$ %v");
  spdlog::set_level(spdlog::level::from_str(level));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"tiltgate: Modbus/TCP gateway for Rieker Flex and Spectron Dyna inclinometers"};
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
  tiltgate::RiekerSimOptions rieker_options;
  auto* rieker = sim->add_subcommand("rieker", "Rieker Flex H6 / H4360 sensors");
  rieker->add_option("--sensors", rieker_options.sensors, "model:address[,model:address...]")
      ->capture_default_str();
  rieker->add_option("--link", rieker_options.link, "also make this symlink to the pty");
  rieker->add_option("--pace-baud", rieker_options.pace_baud,
                     "pace replies at this baud rate (0: no pacing)");

  tiltgate::SpectronSimOptions spectron_options;
  auto* spectron = sim->add_subcommand("spectron", "Spectron SPECTROTILT Dyna modules");
  spectron->add_option("--protocol", spectron_options.protocol, "9bit or modbus (Modbus-ASCII)")
      ->check(CLI::IsMember({"9bit", "modbus"}))
      ->capture_default_str();
  spectron->add_option("--sensors", spectron_options.sensors, "dyna:address[,dyna:address...]")
      ->capture_default_str();
  spectron->add_option("--link", spectron_options.link, "also make this symlink to the pty");
  spectron->add_option("--pace-baud", spectron_options.pace_baud,
                       "pace replies at this baud rate (0: no pacing)");

  CLI11_PARSE(app, argc, argv);
  set_up_logging(log_level);

  if (*run) return tiltgate::run_command(config_path);
  if (*check) return tiltgate::check_command(config_path);
  if (*map) return tiltgate::map_command(config_path, format);
  if (*demo) return tiltgate::demo_command(demo_options);
  if (*rieker) return tiltgate::sim_rieker_command(rieker_options);
  if (*spectron) return tiltgate::sim_spectron_command(spectron_options);
  return 2;
}
