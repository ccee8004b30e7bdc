#include "commission_cli/commission_run.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <nlohmann/json.hpp>

#include "commission_wire/event_json.h"
#include "control/gateway_command.h"

namespace tiltgate {

namespace {

// The options' files as the gateway, whose working directory is not the command's, finds them.
CommandRequest with_absolute_paths(CommandRequest request) {
  namespace fs = std::filesystem;
  for (std::string* path : {&request.bus.config, &request.bus.device})
    if (!path->empty()) *path = fs::absolute(*path).string();
  return request;
}

// Connects to the gateway that serves the target's bus: none when no gateway does (the command
// then opens the tty itself), unless --via-gateway required one; an error says why not.
Expected<std::unique_ptr<GatewayCommand>, CommissionBus::OpenError> serving_gateway(
    boost::asio::io_context& io, const CommissionTarget& target) {
  if (target.control_socket.empty()) return std::unique_ptr<GatewayCommand>{};
  auto gateway = GatewayCommand::connect(io.get_executor(), target.control_socket, target.bus.port);
  if (!gateway) {
    const bool elsewhere = gateway.error().kind != GatewayCommand::ConnectError::failed;
    if (!target.via_gateway && elsewhere) return std::unique_ptr<GatewayCommand>{};
    return Unexpected{CommissionBus::OpenError{1, gateway.error().message}};
  }
  const control::BusGranted& bus = (*gateway)->bus();
  if (bus.protocol != target.bus.protocol)
    return Unexpected{CommissionBus::OpenError{
        2, fmt::format("the running gateway's bus {} on {} speaks {}, not {} (--protocol)",
                       bus.name, target.bus.port, bus.protocol, target.bus.protocol)}};
  return std::move(*gateway);
}

// The gateway runs the command; its events go to the request's renderer as they come.
int run_through_gateway(boost::asio::io_context& io, std::string_view command,
                        const CommissionTarget& target, GatewayCommand& gateway,
                        const GatewayRequest& through) {
  const control::BusGranted& bus = gateway.bus();
  std::cerr << fmt::format("through the running gateway: bus {} ({} baud), control socket {}\n",
                           bus.name, bus.baud, target.control_socket);
  if (bus.baud != target.bus.baud)
    std::cerr << fmt::format("note: the gateway runs {} at {} baud; that rate is used, not {}\n",
                             bus.name, bus.baud, target.bus.baud);
  const std::string request = request_json(with_absolute_paths(through.request)).dump();
  bool stopping = false;
  int exit_code = 1;
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  std::function<void(const boost::system::error_code&, int)> on_signal =
      [&](const boost::system::error_code& ec, int) {
        if (ec) return;
        stopping = true;
        gateway.stop();
        signals.async_wait(on_signal);  // a second Ctrl-C stops waiting for the gateway
      };
  signals.async_wait(on_signal);
  const auto on_event = [&](const std::string& text) {
    const nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
    Expected<CommissionEvent, std::string> event = Unexpected{std::string("not JSON")};
    if (!json.is_discarded()) event = event_from_json(json);
    if (event)
      through.report(*event);
    else
      std::cerr << "tiltgate " << command << ": the gateway sent an event this command cannot "
                << "read (" << event.error() << ")\n";
  };
  boost::asio::co_spawn(
      io,
      [&]() -> boost::asio::awaitable<void> {
        auto ran = co_await gateway.run(request, on_event);
        signals.cancel();
        if (!ran) {
          std::cerr << "tiltgate " << command << ": " << ran.error() << "\n";
          co_return;
        }
        exit_code = *ran;
      },
      boost::asio::detached);
  io.run();
  if (stopping) return 0;
  return through.after ? through.after(exit_code) : exit_code;
}

}  // namespace

int report_usage_errors(std::string_view command, const UsageErrors& errors) {
  for (const std::string& error : errors)
    std::cerr << "tiltgate " << command << ": " << error << "\n";
  std::cerr << "Run with --help for more information.\n";
  return 2;
}

int run_commissioning(std::string_view command, const BusOptions& options, FamilyList families,
                      CommissionWork work, GatewayRequest through_gateway) {
  const auto target = resolve_bus_options(options, families);
  if (!target) return report_usage_errors(command, target.error());
  return run_commissioning_on(command, *target, std::move(work), std::move(through_gateway));
}

int run_commissioning_on(std::string_view command, const CommissionTarget& target,
                         CommissionWork work, GatewayRequest through_gateway) {
  boost::asio::io_context io;
  auto gateway = serving_gateway(io, target);
  if (!gateway) {
    std::cerr << "tiltgate " << command << ": " << gateway.error().message << "\n";
    return gateway.error().exit_code;
  }
  if (*gateway) return run_through_gateway(io, command, target, **gateway, through_gateway);
  auto bus = CommissionBus::open(io.get_executor(), target);
  if (!bus) {
    std::cerr << "tiltgate " << command << ": " << bus.error().message << "\n";
    return bus.error().exit_code;
  }
  bool stopping = false;
  int exit_code = 0;
  boost::asio::signal_set signals(io, SIGINT, SIGTERM);
  signals.async_wait([&](const boost::system::error_code& ec, int) {
    if (ec) return;
    stopping = true;
    (*bus)->stop();
  });
  boost::asio::co_spawn(
      io,
      [&]() -> boost::asio::awaitable<void> {
        exit_code = co_await work(**bus, stopping);
        signals.cancel();
        (*bus)->stop();
      },
      boost::asio::detached);
  io.run();
  return stopping ? 0 : exit_code;
}

}  // namespace tiltgate
