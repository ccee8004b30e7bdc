#include "commission/commission_run.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/signal_set.hpp>
#include <csignal>
#include <iostream>

namespace tiltgate {

int report_usage_errors(std::string_view command, const UsageErrors& errors) {
  for (const std::string& error : errors)
    std::cerr << "tiltgate " << command << ": " << error << "\n";
  std::cerr << "Run with --help for more information.\n";
  return 2;
}

int run_commissioning(std::string_view command, const BusOptions& options, FamilyList families,
                      CommissionWork work) {
  const auto target = resolve_bus_options(options, families);
  if (!target) return report_usage_errors(command, target.error());
  return run_commissioning_on(command, *target, std::move(work));
}

int run_commissioning_on(std::string_view command, const CommissionTarget& target,
                         CommissionWork work) {
  boost::asio::io_context io;
  auto bus = CommissionBus::open(io.get_executor(), target);
  if (!bus) {
    std::cerr << "tiltgate " << command << ": " << bus.error().message << "\n";
    return bus.error().exit_code;
  }
  for (const std::string& note : (*bus)->opening_notes()) std::cerr << note << "\n";
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
