// `demo` and `sim rieker`: the gateway on simulated sensors, and the simulator on its own.
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

// The demo plant: two H6 on a boom and one H4360 on the mast, on one bus at the factory baud.
constexpr const char* kDemoSensors = "h6:223,h6:224,h4360:101";

Config demo_config(const DemoOptions& options, const std::string& tty) {
  Config config;
  config.path = "(demo)";
  config.server.listen = options.listen;
  config.server.port = options.port;
  config.server.writes = true;
  BusConfig bus;
  bus.name = "demo-bus";
  bus.port = tty;
  bus.baud = 125000;
  config.buses.push_back(bus);
  const struct { const char* name; const char* model; std::uint32_t address; } sensors[] = {
      {"boom-left", "h6", 223}, {"boom-right", "h6", 224}, {"mast", "h4360", 101}};
  std::uint8_t unit = 1;
  for (const auto& s : sensors) {
    SensorConfig sensor;
    sensor.name = s.name;
    sensor.bus = bus.name;
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
      "Ctrl-C stops.\n",
      config.sensors.size(), host, port, port, host, port, host, port, host);
  std::cout.flush();
}

}  // namespace

int demo_command(const DemoOptions& options) {
  boost::asio::io_context io;
  auto sensors = rieker::parse_sensor_spec(kDemoSensors);
  if (!sensors) {
    spdlog::critical("demo: {}", sensors.error());
    return 1;
  }
  rieker::RiekerSimulatorOptions sim_options;
  sim_options.sensors = std::move(*sensors);
  sim_options.pace_baud = 125000;  // real wire time, so the demo behaves like a plant
  rieker::RiekerSimulator simulator(io, sim_options);
  if (auto started = simulator.start(); !started) {
    spdlog::critical("demo: simulator: {}", started.error());
    return 1;
  }
  const Config config = demo_config(options, simulator.slave_path());
  Gateway gateway(io, config);
  if (auto started = gateway.start(); !started) {
    spdlog::critical("demo: {}", started.error());
    return 1;
  }
  print_demo_help(config, gateway);
  run_until_signal(io, [&] {
    gateway.stop();
    simulator.stop();
  });
  return 0;
}

int sim_rieker_command(const RiekerSimOptions& options) {
  auto sensors = rieker::parse_sensor_spec(options.sensors);
  if (!sensors) {
    std::cerr << "tiltgate sim rieker: --sensors: " << sensors.error() << "\n";
    return 1;
  }
  boost::asio::io_context io;
  rieker::RiekerSimulatorOptions sim_options;
  sim_options.sensors = std::move(*sensors);
  sim_options.link_path = options.link;
  if (options.pace_baud > 0) sim_options.pace_baud = options.pace_baud;
  rieker::RiekerSimulator simulator(io, sim_options);
  if (auto started = simulator.start(); !started) {
    std::cerr << "tiltgate sim rieker: " << started.error() << "\n";
    return 1;
  }
  // The path goes to stdout, alone on its line, so a script can read it.
  std::cout << (options.link.empty() ? simulator.slave_path() : options.link) << std::endl;
  spdlog::info("simulating {} Rieker sensor(s) on {}", simulator.sensor_count(),
               simulator.slave_path());
  run_until_signal(io, [&] { simulator.stop(); });
  return 0;
}

}  // namespace tiltgate
