// `demo`, `sim rieker` and `sim spectron`: the gateway on simulated sensors, and the
// simulators on their own.
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <fmt/format.h>
#include <iostream>
#include <spdlog/spdlog.h>

#include "gateway/commands.h"
#include "gateway/gateway.h"
#include "rieker/sensor_spec.h"
#include "rieker/simulator.h"
#include "spectron/sensor_spec.h"
#include "spectron/simulator.h"

namespace tiltgate {

namespace {

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
}

// The demo plant: two H6 on a boom and one H4360 on the mast, on one bus at the factory baud;
// and a Dyna on the slewing ring, on a Modbus-ASCII bus at the rate of the note's example.
constexpr const char* kDemoSensors = "h6:223,h6:224,h4360:101";
constexpr const char* kDemoDynas = "dyna:1";
constexpr std::uint32_t kDemoDynaBaud = 28800;

Config demo_config(const DemoOptions& options, const std::string& rieker_tty,
                   const std::string& dyna_tty) {
  Config config;
  config.path = "(demo)";
  config.server.listen = options.listen;
  config.server.port = options.port;
  config.server.writes = true;
  BusConfig rieker_bus;
  rieker_bus.name = "demo-bus";
  rieker_bus.port = rieker_tty;
  rieker_bus.protocol = "rieker";
  rieker_bus.baud = 125000;
  config.buses.push_back(rieker_bus);
  BusConfig dyna_bus;
  dyna_bus.name = "demo-dyna-bus";
  dyna_bus.port = dyna_tty;
  dyna_bus.protocol = "spectron-modbus";
  dyna_bus.baud = kDemoDynaBaud;
  config.buses.push_back(dyna_bus);
  const struct {
    const char* name;
    const char* bus;
    const char* model;
    std::uint32_t address;
  } sensors[] = {{"boom-left", "demo-bus", "h6", 223},
                 {"boom-right", "demo-bus", "h6", 224},
                 {"mast", "demo-bus", "h4360", 101},
                 {"slewing-ring", "demo-dyna-bus", "dyna", 1}};
  std::uint8_t unit = 1;
  for (const auto& s : sensors) {
    SensorConfig sensor;
    sensor.name = s.name;
    sensor.bus = s.bus;
    sensor.model = s.model;
    sensor.address = s.address;
    sensor.unit_id = unit++;
    config.sensors.push_back(sensor);
  }
  return config;
}

void print_demo_help(const Config& config, const Gateway& gateway) {
  std::cout << export_markdown(gateway.unit_maps());
  const auto port = gateway.port();
  const auto host = config.server.listen == "0.0.0.0" ? std::string("127.0.0.1") : config.server.listen;
  std::cout << fmt::format(
      "tiltgate demo: {} simulated sensors served on {}:{} (writes enabled). Try:\n"
      "  mbpoll -m tcp -p {} -a 1 -t 3:float -B -r 1 -c 2 -1 {}   # unit 1 angle_x, angle_y\n"
      "  mbpoll -m tcp -p {} -a 3 -t 3 -r 7 -c 10 -1 {}           # unit 3 status block\n"
      "  mbpoll -m tcp -p {} -a 1 -t 4 -r 1 -1 {} 2               # unit 1 filter := 2\n"
      "  mbpoll -m tcp -p {} -a 4 -t 3:float -B -r 1 -c 1 -1 {}   # unit 4 (Dyna) angle\n"
      "  mbpoll -m tcp -p {} -a 4 -t 3 -r 103 -c 1 -1 {}          # unit 4 raw temperature\n"
      "Ctrl-C stops.\n",
      config.sensors.size(), host, port, port, host, port, host, port, host, port, host, port,
      host);
  std::cout.flush();
}

// `tiltgate sim FAMILY`: serves a simulator's bus until SIGINT/SIGTERM. The path goes to
// stdout, alone on its line, so a script can read it.
template <class Simulator, class Options>
int serve_simulator(const char* family, const std::string& what, Options options) {
  boost::asio::io_context io;
  const std::string link = options.link_path;
  Simulator simulator(io, std::move(options));
  if (auto started = simulator.start(); !started) {
    std::cerr << "tiltgate sim " << family << ": " << started.error() << "\n";
    return 1;
  }
  std::cout << (link.empty() ? simulator.slave_path() : link) << std::endl;
  spdlog::info("simulating {} {} on {}", simulator.sensor_count(), what, simulator.slave_path());
  run_until_signal(io, [&] { simulator.stop(); });
  return 0;
}

}  // namespace

int demo_command(const DemoOptions& options) {
  boost::asio::io_context io;
  auto sensors = rieker::parse_sensor_spec(kDemoSensors);
  auto dynas = spectron::parse_sensor_spec(kDemoDynas, spectron::Protocol::modbus_ascii);
  if (!sensors || !dynas) {
    spdlog::critical("demo: {}", sensors ? dynas.error() : sensors.error());
    return 1;
  }
  rieker::RiekerSimulatorOptions sim_options;
  sim_options.sensors = std::move(*sensors);
  sim_options.pace_baud = 125000;  // real wire time, so the demo behaves like a plant
  rieker::RiekerSimulator simulator(io, sim_options);
  spectron::DynaSimulatorOptions dyna_options;
  dyna_options.protocol = spectron::Protocol::modbus_ascii;
  dyna_options.sensors = std::move(*dynas);
  dyna_options.pace_baud = kDemoDynaBaud;
  spectron::DynaSimulator dyna_simulator(io, dyna_options);
  for (auto started : {simulator.start(), dyna_simulator.start()}) {
    if (!started) {
      spdlog::critical("demo: simulator: {}", started.error());
      return 1;
    }
  }
  const Config config = demo_config(options, simulator.slave_path(), dyna_simulator.slave_path());
  Gateway gateway(io, config);
  if (auto started = gateway.start(); !started) {
    spdlog::critical("demo: {}", started.error());
    return 1;
  }
  print_demo_help(config, gateway);
  run_until_signal(io, [&] {
    gateway.stop();
    simulator.stop();
    dyna_simulator.stop();
  });
  return 0;
}

int sim_rieker_command(const RiekerSimOptions& options) {
  auto sensors = rieker::parse_sensor_spec(options.sensors);
  if (!sensors) {
    std::cerr << "tiltgate sim rieker: --sensors: " << sensors.error() << "\n";
    return 1;
  }
  rieker::RiekerSimulatorOptions sim_options;
  sim_options.sensors = std::move(*sensors);
  sim_options.link_path = options.link;
  if (options.pace_baud > 0) sim_options.pace_baud = options.pace_baud;
  return serve_simulator<rieker::RiekerSimulator>("rieker", "Rieker sensor(s)", sim_options);
}

int sim_spectron_command(const SpectronSimOptions& options) {
  const auto protocol =
      options.protocol == "modbus" ? spectron::Protocol::modbus_ascii : spectron::Protocol::nine_bit;
  auto sensors = spectron::parse_sensor_spec(options.sensors, protocol);
  if (!sensors) {
    std::cerr << "tiltgate sim spectron: --sensors: " << sensors.error() << "\n";
    return 1;
  }
  spectron::DynaSimulatorOptions sim_options;
  sim_options.protocol = protocol;
  sim_options.sensors = std::move(*sensors);
  sim_options.link_path = options.link;
  if (options.pace_baud > 0) sim_options.pace_baud = options.pace_baud;
  const std::string what = std::string(spectron::protocol_name(protocol)) + " Dyna module(s)";
  return serve_simulator<spectron::DynaSimulator>("spectron", what, sim_options);
}

}  // namespace tiltgate
