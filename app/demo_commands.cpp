// `demo` and `sim FAMILY`: the gateway on simulated sensors (each family's demo bus), and a
// family's simulator on its own.
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <fmt/format.h>
#include <iostream>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <memory>
#include <vector>

#include "app/config_reload.h"
#include "app/demo_accounts.h"
#include "app/demo_commands.h"
#include "app/simulator_console.h"
#include "app/demo_sensor_keys.h"
#include "app/served_gateway.h"
#include "app/service_notify.h"
#include "config/config_loader.h"
#include "config/machine_checks.h"
#include "toml/toml_string.h"

namespace tiltgate {

namespace {

struct DemoOptions {
  std::string listen = "127.0.0.1";
  std::uint16_t port = 1502;
  std::uint16_t http_port = 8080;  // the HTTP status API and metrics, on `listen`; 0: off
  std::string mqtt_host;           // the MQTT feed's broker, under tiltgate/demo/; empty: off
  std::uint16_t mqtt_port = 1883;
  // The Sparkplug B edge node's broker, group "tiltgate-demo", edge node "demo"; empty: off.
  std::string sparkplug_host;
  std::uint16_t sparkplug_port = 1883;
  // Where commissioning commands reach the demo's buses (--via-gateway); empty: the demo's own
  // temporary folder, so that it neither takes nor is refused a running service's socket.
  std::string control_socket;
  bool map = false;  // print every unit's register map before the "Try:" lines
  // The web console without accounts: the read-only status page, its API open to all.
  bool no_accounts = false;
};

// Runs `io` until SIGINT/SIGTERM, then calls `stop` and returns.
template <class Stop>
void run_until_signal(boost::asio::io_context& io, Stop stop) {
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int signal) {
    if (ec) return;
    spdlog::info("signal {}: shutting down", signal);
    stop();
    io.stop();
  });
  io.run();
  finish_stopped(io);
}

// The demo's configuration file: every family's demo bus, its sensors numbered from unit id 1
// in family order, in the demo's folder with the files the sensors' own keys name. A file, not
// a configuration made in memory, so the console's Configuration tab, scans, raw frames and
// applies work on the demo as on a plant (docs/web-console.md, "Try it").
Expected<std::string, std::string> demo_config_text(const DemoOptions& options,
                                                    FamilyCommandsList demos,
                                                    const std::vector<std::string>& ttys,
                                                    const std::filesystem::path& folder) {
  using toml_input::toml_string;
  const auto path = [&](std::string_view name) { return toml_string((folder / name).string()); };
  std::string text = fmt::format(
      "# tiltgate demo: written for this run into its temporary folder, gone when it stops.\n"
      "[server]\nlisten = {}\nport = {}\nwrites = true\ncontrol_socket = {}\n"
      // The demo's own folder: a demo on a gateway must not write into the service's audit
      // trail or stores, nor take (or be refused) them.
      "state_dir = {}\n",
      toml_string(options.listen), options.port,
      options.control_socket.empty() ? path("control.sock") : toml_string(options.control_socket),
      path("state"));
  text += fmt::format("\n[http]\n");
  if (options.http_port == 0)
    text += "enabled = false\n";
  else
    text += fmt::format("listen = {}\nport = {}\n", toml_string(options.listen), options.http_port);
  // Accounts made for this run (app/demo_accounts.h); the file is written before the start.
  if (options.http_port != 0 && !options.no_accounts)
    text += fmt::format("users_file = {}\n", path("users"));
  if (!options.mqtt_host.empty())
    text += fmt::format("\n[mqtt]\nhost = {}\nport = {}\nclient_id = \"tiltgate-demo-{}\"\n"
                        "topic_prefix = \"tiltgate/demo\"\n",
                        toml_string(options.mqtt_host), options.mqtt_port, ::getpid());
  if (!options.sparkplug_host.empty())
    // Its bdSeq starts at 0 every run, in the demo's folder; DCMD writes on, as Modbus writes.
    text += fmt::format("\n[sparkplug]\nhost = {}\nport = {}\ngroup_id = \"tiltgate-demo\"\n"
                        "edge_node_id = \"demo\"\nclient_id = \"tiltgate-demo-sparkplug-{}\"\n"
                        "commands = true\n",
                        toml_string(options.sparkplug_host), options.sparkplug_port, ::getpid());
  int unit = 1;
  for (std::size_t i = 0; i < demos.size(); ++i) {
    const DemoBus& demo = demos[i]->demo;
    text += fmt::format("\n[[bus]]\nname = {}\nport = {}\nprotocol = {}\nbaud = {}\n",
                        toml_string(demo.bus_name), toml_string(ttys[i]),
                        toml_string(demo.protocol), demo.baud);
    for (const DemoSensor& sensor : demo.sensors) {
      auto keys = demo_sensor_keys(sensor, folder);
      if (!keys) return Unexpected{keys.error()};
      text += fmt::format("\n[[sensor]]\nname = {}\nbus = {}\nmodel = {}\naddress = {}\n"
                          "unit_id = {}\n{}",
                          toml_string(sensor.name), toml_string(demo.bus_name),
                          toml_string(sensor.model), sensor.address, unit++, *keys);
    }
  }
  return text;
}

// The console's address and the accounts to log in with, beside the Modbus lines.
void print_console_help(const Config& config, const std::vector<DemoAccount>& accounts) {
  if (!config.http.enabled) return;
  const std::string host =
      config.http.listen == "0.0.0.0" ? std::string("127.0.0.1") : config.http.listen;
  if (accounts.empty()) {
    std::cout << fmt::format("The status page: http://{}:{}/ (no accounts: read-only)\n", host,
                             config.http.port);
    return;
  }
  std::cout << fmt::format(
      "The web console: http://{}:{}/ from this machine. Log in as (passwords for this run "
      "only):\n",
      host, config.http.port);
  for (const DemoAccount& account : accounts) {
    const std::string_view may = account.role == Role::admin ? "every change, scans, raw frames"
                                 : account.role == Role::operator_ ? "zero, filter"
                                                                   : "reads only";
    std::cout << fmt::format("  {:<9} {}   ({})\n", account.name, account.password, may);
  }
}

void print_demo_help(const Config& config, const Gateway& gateway, FamilyCommandsList demos,
                     bool map, const std::vector<DemoAccount>& accounts) {
  if (map) std::cout << export_markdown(gateway.unit_maps());
  const auto port = gateway.port();
  const auto host = config.server.listen == "0.0.0.0" ? std::string("127.0.0.1") : config.server.listen;
  std::cout << fmt::format(
      "tiltgate demo: {} simulated sensors served on {}:{} (writes enabled). Try:\n",
      config.sensors.size(), host, port);
  int first_unit = 1;
  for (const FamilyCommands* family : demos) {
    const int last_unit = first_unit + int(family->demo.sensors.size()) - 1;
    for (std::string_view example : family->demo.examples)
      std::cout << fmt::format(fmt::runtime(example), fmt::arg("port", port),
                               fmt::arg("host", host), fmt::arg("unit", first_unit),
                               fmt::arg("last_unit", last_unit))
                << "\n";
    first_unit = last_unit + 1;
  }
  // The commissioning commands, through the demo's own control socket, on its first bus.
  const BusConfig& bus = config.buses.front();
  std::cout << fmt::format(
      "Commissioning commands reach the simulated buses through the demo's control socket "
      "{}:\n"
      "  tiltgate info --port {} --protocol {} --address {} --via-gateway --control-socket {}\n",
      config.server.control_socket, bus.port, bus.protocol, config.sensors.front().address,
      config.server.control_socket);
  for (const BusConfig& b : config.buses)
    std::cout << fmt::format("  bus {}: --port {} --protocol {}\n", b.name, b.port, b.protocol);
  print_console_help(config, accounts);
  std::cout << fmt::format("The configuration is {} (the console's Configuration tab edits it).\n",
                           config.path);
  for (const FamilyCommands* family : demos)
    for (const DemoSensor& spare : family->demo.spare)
      std::cout << fmt::format(
          "A sensor is fitted on {} at address {} but not configured: scan the bus in the "
          "console's Buses tab and add it.\n",
          family->demo.bus_name, spare.address);
  if (!map) std::cout << "The register maps: tiltgate demo --map (or docs/default-maps.md).\n";
  std::cout << "Ctrl-C stops.\n";
  std::cout.flush();
}

int demo_command(const DemoOptions& options, FamilyCommandsList all_commands) {
  boost::asio::io_context io;
  // Declared first, so it goes last: the sensors' drivers read their files while they run.
  auto folder = DemoFolder::create();
  if (!folder) {
    spdlog::critical("demo: {}", folder.error());
    return 1;
  }
  // A family whose demo has no sensor gets no bus: an empty simulated bus would only be noise
  // in the demo.
  std::vector<const FamilyCommands*> demo_commands;
  std::vector<const FamilyDescriptor*> demo_families;
  for (const FamilyCommands* family : all_commands) {
    if (family->demo.sensors.empty()) continue;
    demo_commands.push_back(family);
    demo_families.push_back(family->family);
  }
  const FamilyCommandsList demos = demo_commands;
  const FamilyList families = demo_families;
  std::vector<std::unique_ptr<BusSimulator>> simulators;
  std::vector<std::string> ttys;
  for (const FamilyCommands* family : demos) {
    SimulatorSetup setup = demo_simulator_setup(*family);
    setup.pace_baud = family->demo.baud;  // real wire time, so the demo behaves like a plant
    setup.sway = true;
    auto simulator = family->simulator.make(io, setup);
    if (!simulator) {
      spdlog::critical("demo: {}", simulator.error());
      return 1;
    }
    if (auto started = (*simulator)->start(); !started) {
      spdlog::critical("demo: simulator: {}", started.error());
      return 1;
    }
    ttys.push_back((*simulator)->slave_path());
    simulators.push_back(std::move(*simulator));
  }
  const auto text = demo_config_text(options, demos, ttys, folder->path());
  if (!text) {
    spdlog::critical("demo: {}", text.error());
    return 1;
  }
  const std::string config_path = (folder->path() / "demo.toml").string();
  if (auto written = write_demo_file(config_path, *text); !written) {
    spdlog::critical("demo: {}", written.error());
    return 1;
  }
  auto loaded = checked_on_this_machine(load_config_file(config_path, families));
  if (!loaded) {
    for (const ConfigError& error : loaded.error()) spdlog::critical("demo: {}", error.to_string());
    return 1;
  }
  const Config& config = *loaded;
  std::vector<DemoAccount> accounts;
  if (!config.http.users_file.empty()) {
    auto made = make_demo_accounts(config.http.users_file);
    if (!made) {
      spdlog::critical("demo: the console's accounts: {}", made.error());
      return 1;
    }
    accounts = std::move(*made);
  }
  boost::asio::signal_set hangups(io, SIGHUP);  // before start(): a SIGHUP reloads the file
  ServedGateway served(io, config, families);
  Gateway& gateway = served.gateway();
  if (auto started = gateway.start(); !started) {
    spdlog::critical("demo: {}", started.error());
    return 1;
  }
  served.start_as_user();  // the demo stays the user it was started as
  print_demo_help(config, gateway, demos, options.map, accounts);
  // A console apply reloads the demo's file as `systemctl reload` reloads a service's.
  ServiceNotifier notifier(io);
  reload_on_sighup(hangups, gateway, config_path, families, notifier);
  run_until_signal(io, [&] {
    hangups.cancel();
    gateway.stop();
    for (auto& simulator : simulators) simulator->stop();
  });
  return 0;
}

int sim_command(const FamilyCommands& family, const SimulatorSetup& setup) {
  const std::string command(family.simulator.command);
  boost::asio::io_context io;
  auto simulator = family.simulator.make(io, setup);
  if (!simulator) {
    std::cerr << "tiltgate sim " << command << ": --sensors: " << simulator.error() << "\n";
    return 1;
  }
  BusSimulator& running = **simulator;
  if (auto started = running.start(); !started) {
    std::cerr << "tiltgate sim " << command << ": " << started.error() << "\n";
    return 1;
  }
  // The path goes to stdout, alone on its line, so a script can read it.
  std::cout << (setup.link.empty() ? running.slave_path() : setup.link) << std::endl;
  spdlog::info("simulating {} {} on {}", running.sensor_count(), running.what(),
               running.slave_path());
  if (!setup.second_master.empty()) spdlog::info("second master on {}", setup.second_master);
  SimulatorConsole console(io, running, STDIN_FILENO,
                           [](const std::string& answer) { std::cout << answer << std::endl; });
  if (console.start()) spdlog::info("reading commands from standard input");
  run_until_signal(io, [&] {
    console.stop();
    running.stop();
  });
  return 0;
}

}  // namespace

Subcommand add_demo(CLI::App& app, FamilyCommandsList commands) {
  auto options = std::make_shared<DemoOptions>();
  CLI::App* demo = app.add_subcommand("demo", "serve built-in simulated sensors (writes enabled)");
  demo->add_option("--listen", options->listen, "address to bind")->capture_default_str();
  demo->add_option("--port", options->port, "Modbus TCP port")->capture_default_str();
  demo->add_option("--http-port", options->http_port,
                   "HTTP status API and metrics port (0: off)")
      ->capture_default_str();
  demo->add_option("--mqtt-host", options->mqtt_host,
                   "MQTT broker to publish the sensors to, under tiltgate/demo/ (default: off)");
  demo->add_option("--mqtt-port", options->mqtt_port, "MQTT broker port")->capture_default_str();
  demo->add_option("--sparkplug-host", options->sparkplug_host,
                   "MQTT broker to run a Sparkplug B edge node on: group tiltgate-demo, edge node "
                   "demo, DCMD writes on (default: off)");
  demo->add_option("--sparkplug-port", options->sparkplug_port, "its port")->capture_default_str();
  demo->add_option("--control-socket", options->control_socket,
                   "where commissioning commands reach the demo's buses (--via-gateway) "
                   "(default: control.sock in the demo's temporary folder)");
  demo->add_flag("--map", options->map, "print every unit's register map before the Try lines");
  demo->add_flag("--no-accounts", options->no_accounts,
                 "serve the read-only status page, its API open to all, instead of the web "
                 "console with three accounts made for this run");
  return {demo, [options, commands] { return demo_command(*options, commands); }};
}

Subcommand add_sim(CLI::App& app, FamilyCommandsList commands) {
  CLI::App* sim = app.add_subcommand("sim", "run a simulated sensor bus on a pseudo-terminal");
  sim->require_subcommand(1);
  // One `sim` subcommand per family, each with its own setup.
  struct FamilySim {
    const FamilyCommands* family = nullptr;
    CLI::App* cli = nullptr;
    SimulatorSetup setup;
    std::string protocol;  // the short name chosen with --protocol; empty: the family has one
  };
  auto sims = std::make_shared<std::vector<FamilySim>>(commands.size());
  for (std::size_t i = 0; i < commands.size(); ++i) {
    FamilySim& entry = (*sims)[i];
    entry.family = commands[i];
    const SimulatorDescriptor& simulator = commands[i]->simulator;
    const FamilyDescriptor& family = *commands[i]->family;
    SimulatorSetup& setup = entry.setup;
    CLI::App* command =
        sim->add_subcommand(std::string(simulator.command), std::string(simulator.help));
    // A family of several protocols chooses one by its short name, the first by default.
    const std::vector<std::string> choices = simulator_protocol_choices(family);
    if (!choices.empty()) {
      entry.protocol = choices.front();
      command->add_option("--protocol", entry.protocol, simulator_protocols_help(family))
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
    command->add_option("--second-master", setup.second_master,
                        "also serve a second master's pty on the same line, with this symlink "
                        "to it (a warm-standby pair): each master hears the other and every "
                        "reply, and bytes on the line at once collide");
    command->add_option("--stats", setup.stats,
                        "rewrite this file every 100 ms with the line's counters as JSON: "
                        "bytes each master sent and received, collisions, device replies");
    entry.cli = command;
  }
  return {sim, [sims] {
            for (FamilySim& entry : *sims) {
              if (!*entry.cli) continue;
              entry.setup.protocol = protocol_of_choice(*entry.family->family, entry.protocol);
              return sim_command(*entry.family, entry.setup);
            }
            return 2;
          }};
}

}  // namespace tiltgate
