#include "monitoring_cli/baseline_command.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "monitoring_cli/configured_sensor.h"
#include "control/gateway_command.h"

namespace tiltgate {

namespace {

struct BaselineOptions {
  std::string config;
  std::string control_socket;
  std::string sensor;
  bool current = false;
  bool clear = false;
  std::optional<double> x;
  std::optional<double> y;
};

int usage_error(const std::string& message) {
  std::cerr << "tiltgate baseline: " << message << "\nRun with --help for more information.\n";
  return 2;
}

nlohmann::json request_of(const BaselineOptions& o) {
  nlohmann::json request{{"command", "baseline"}, {"sensor", o.sensor}, {"set", "show"}};
  if (o.current) request["set"] = "current";
  if (o.clear) request["set"] = "clear";
  if (o.x) {
    request["set"] = "value";
    request["x"] = *o.x;
    if (o.y) request["y"] = *o.y;
  }
  return request;
}

int run_baseline(const BaselineOptions& o, FamilyList families) {
  const auto configured = load_configured_sensor("baseline", o.config, o.sensor, families);
  if (!configured) return 1;
  const SensorConfig* sensor = &configured->sensor;
  const Config* loaded = &configured->config;
  const std::string socket =
      o.control_socket.empty() ? loaded->server.control_socket : o.control_socket;
  boost::asio::io_context io;
  auto gateway = GatewayCommand::connect(io.get_executor(), socket, sensor->bus);
  if (!gateway) {
    std::cerr << "tiltgate baseline: " << gateway.error().message << "\n";
    return 1;
  }
  int exit_code = 1;
  const auto on_event = [&](const std::string& text) {
    const nlohmann::json event = nlohmann::json::parse(text, nullptr, false);
    const std::string kind = event.is_object() ? event.value("event", "") : "";
    if (kind == "baseline") {
      std::cout << fmt::format("{}: baseline x {:g} y {:g} deg", event.value("sensor", ""),
                               event.value("x", 0.0), event.value("y", 0.0));
      if (event.value("stored", false))
        std::cout << fmt::format(", set by {}", event.value("by", ""));
      else
        std::cout << ", the configuration's";
      std::cout << "\n";
    } else if (kind == "error") {
      std::cerr << "tiltgate baseline: " << event.value("message", std::string("failed")) << "\n";
    }
  };
  boost::asio::co_spawn(
      io,
      [&]() -> boost::asio::awaitable<void> {
        auto done = co_await (*gateway)->run(request_of(o).dump(), on_event);
        if (!done) {
          std::cerr << "tiltgate baseline: " << done.error() << "\n";
          exit_code = 1;
        } else {
          exit_code = *done;
        }
      },
      boost::asio::detached);
  io.run();
  return exit_code;
}

}  // namespace

Subcommand add_baseline(CLI::App& app, FamilyList families) {
  auto options = std::make_shared<BaselineOptions>();
  CLI::App* command = app.add_subcommand(
      "baseline", "show or set a sensor's baseline (its installation reading) in the running "
                  "gateway: readings from it and the displacement are measured from there");
  command->add_option("-c,--config", options->config, "the gateway's configuration")
      ->required();
  command->add_option("--control-socket", options->control_socket,
                      "the gateway's control socket (default: the configuration's)");
  command->add_option("--sensor", options->sensor, "the sensor's name")->required();
  command->add_flag("--current", options->current, "take the sensor's current reading");
  command->add_flag("--clear", options->clear,
                    "forget the baseline set since: the configuration's applies again");
  command->add_option("--x", options->x, "the baseline's X, degrees after mounting");
  command->add_option("--y", options->y, "the baseline's Y (two-axis sensors)");
  return {command, [options, families]() -> int {
            const BaselineOptions& o = *options;
            const int changes = int(o.current) + int(o.clear) + int(o.x.has_value());
            if (changes > 1) return usage_error("give one of --current, --x/--y and --clear");
            if (o.y && !o.x) return usage_error("--y needs --x");
            return run_baseline(o, families);
          }};
}

}  // namespace tiltgate
