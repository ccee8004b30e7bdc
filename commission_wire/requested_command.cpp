#include "commission_wire/requested_command.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <spdlog/spdlog.h>

#include "commission_wire/command_request.h"
#include "commission_wire/event_json.h"
#include "commission/info_engine.h"
#include "commission/raw_engine.h"
#include "commission/scan_engine.h"
#include "commission/set_engine.h"
#include "commission/watch_engine.h"
#include "driver/visible_text.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

std::string joined(const UsageErrors& errors) {
  std::string text;
  for (const std::string& error : errors) text += (text.empty() ? "" : "\n") + error;
  return text;
}

// The bus and sensors the request names, as the command line resolved them; scan's with its
// own options.
struct Resolved {
  CommissionTarget target;
  std::optional<PreparedScan> scan;
};

Expected<Resolved, UsageErrors> resolve(const CommandRequest& request, FamilyList families) {
  if (request.command == "scan") {
    auto prepared = prepare_scan(request.bus, request.scan, families);
    if (!prepared) return Unexpected{prepared.error()};
    CommissionTarget target = prepared->bus;
    return Resolved{std::move(target), std::move(*prepared)};
  }
  if (request.command == "watch")
    if (UsageErrors errors = watch_option_errors(request.watch); !errors.empty())
      return Unexpected{errors};
  auto target = resolve_bus_options(request.bus, families);
  if (!target) return Unexpected{target.error()};
  return Resolved{std::move(*target), std::nullopt};
}

asio::awaitable<int> run_on(CommissionBus& bus, const CommandRequest& request,
                            const Resolved& resolved, FamilyCommandsList commands,
                            const EventSink& report, const bool& stopping) {
  if (request.command == "scan") co_return co_await scan_bus(bus, *resolved.scan, report, stopping);
  if (request.command == "info") co_return co_await show_info(bus, commands, report, stopping);
  if (request.command == "watch")
    co_return co_await watch_sensors(bus, request.watch, report, stopping);
  if (request.command == "raw")
    co_return co_await raw_exchange(bus, request.raw, commands, report, stopping);
  // set: the configuration file is the command's (SetRequest::config_file empty).
  const SetRequest set{request.set, ""};
  co_return co_await set_sensor(bus, set, commands, report, stopping);
}

asio::awaitable<int> run_parsed(FamilyList families, FamilyCommandsList commands,
                                const std::string& text, ServedBus served, WriteOrigin by,
                                const EventSink& report, CommandStop& stop) {
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, false);
  auto request = request_from_json(json);
  if (json.is_discarded() || !request) {
    report(FailedEvent{2, fmt::format("the gateway cannot read the request: {}",
                                      json.is_discarded() ? "not JSON" : request.error())});
    co_return 2;
  }
  auto resolved = resolve(*request, families);
  if (!resolved) {
    report(FailedEvent{2, joined(resolved.error())});
    co_return 2;
  }
  auto line = std::make_unique<ServedBusLine>(std::move(served), std::move(by));
  auto bus = CommissionBus::on_served_line(resolved->target, std::move(line));
  if (!bus) {
    report(FailedEvent{bus.error().exit_code, bus.error().message});
    co_return bus.error().exit_code;
  }
  stop.on_request = [&bus] { (*bus)->stop(); };
  const int code = co_await run_on(**bus, *request, *resolved, commands, report, stop.requested);
  stop.on_request = nullptr;
  co_return stop.requested ? 0 : code;
}

}  // namespace

asio::awaitable<int> run_requested_command(FamilyList families, FamilyCommandsList commands,
                                           std::string request, ServedBus bus, WriteOrigin by,
                                           EventSink report, CommandStop& stop) {
  const std::string bus_name = bus.config.name;
  const std::string who = by.who;
  // Whatever happens to the command, it ends with an event: its line is freed (a sensor it
  // held is polled again) and the failure is said once, in the log and to the command.
  try {
    co_return co_await run_parsed(families, commands, request, std::move(bus), std::move(by),
                                  report, stop);
  } catch (const std::exception& e) {
    stop.on_request = nullptr;
    spdlog::error("control socket: a command on bus {} for {} failed: {}", visible_text(bus_name),
                  visible_text(who), e.what());
    report(FailedEvent{1, fmt::format("the command failed in the gateway: {}", e.what())});
    co_return 1;
  }
}

CommandRunner requested_command_runner(FamilyList families, FamilyCommandsList commands) {
  return [families, commands](std::string request, ServedBus bus, WriteOrigin by,
                              std::function<void(std::string)> emit,
                              CommandStop& stop) -> asio::awaitable<int> {
    const EventSink report = [emit](const CommissionEvent& event) {
      // Text from a device may not be UTF-8: replaced, never a throw on the buses' thread.
      emit(event_json(event).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
    };
    co_return co_await run_requested_command(families, commands, std::move(request),
                                             std::move(bus), std::move(by), report, stop);
  };
}

}  // namespace tiltgate
