// `check`, `map` and `run`: the subcommands that start from a configuration file.
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <fmt/format.h>
#include <iostream>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "config/config_loader.h"
#include "gateway/commands.h"
#include "gateway/gateway.h"
#include "gateway/run_as_user.h"

namespace tiltgate {

namespace {

// Loads and validates; prints every problem to stderr, compiler style.
std::optional<Config> load_or_report(const std::string& path) {
  auto loaded = load_config_file(path);
  if (!loaded) {
    for (const ConfigError& error : loaded.error()) std::cerr << error.to_string() << "\n";
    std::cerr << fmt::format("{}: {} error(s); nothing started\n", path, loaded.error().size());
    return std::nullopt;
  }
  return std::move(*loaded);
}

}  // namespace

int check_command(const std::string& config_path) {
  auto config = load_or_report(config_path);
  if (!config) return 1;
  std::cout << fmt::format("{}: OK ({} bus(es), {} sensor(s))\n", config_path,
                           config->buses.size(), config->sensors.size());
  return 0;
}

int map_command(const std::string& config_path, const std::string& format) {
  auto config = load_or_report(config_path);
  if (!config) return 1;
  std::vector<RegisterMap> maps;
  maps.reserve(config->sensors.size());
  std::vector<UnitMap> units;
  for (const SensorConfig& sensor : config->sensors) {
    maps.push_back(map_for(sensor));
    units.push_back({sensor.unit_id, sensor.name, sensor.model, &maps.back(),
                     config->server.word_order});
  }
  std::cout << (format == "markdown" ? export_markdown(units) : export_csv(units));
  return 0;
}

int run_command(const std::string& config_path) {
  auto config = load_or_report(config_path);
  if (!config) return 1;
  boost::asio::io_context io;
  Gateway gateway(io, *config);
  auto started = gateway.start();
  if (!started) {
    spdlog::critical("{}", started.error());
    return 1;
  }
  // The ttys and listeners are open: root is no longer needed.
  if (!config->server.user.empty()) {
    if (auto switched = run_as_user(config->server.user); !switched) {
      spdlog::critical("{}", switched.error());
      return 1;
    }
    spdlog::info("serving as user {} (uid {})", config->server.user, getuid());
  } else if (geteuid() == 0) {
    spdlog::warn("running as root: set [server] user to serve unprivileged once started "
                 "(README, \"Running without root\")");
  }
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int signal) {
    if (ec) return;
    spdlog::info("signal {}: shutting down", signal);
    gateway.stop();
    io.stop();
  });
  io.run();
  return 0;
}

}  // namespace tiltgate
