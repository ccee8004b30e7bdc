#include "console/bus_actions.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "commission/event_text.h"
#include "commission/raw_engine.h"
#include "driver/hex.h"
#include "driver/visible_text.h"

namespace tiltgate {

namespace asio = boost::asio;
using json = nlohmann::json;

namespace {

// The console's commands read the bus (and a raw frame's sensor) from the served file, as an
// engineer's `tiltgate scan --config FILE --bus NAME` does.
BusOptions console_bus_options(const std::string& config_path, const std::string& bus) {
  BusOptions options;
  options.config = config_path;
  options.bus = bus;
  return options;
}

std::string joined(const UsageErrors& errors) {
  std::string text;
  for (const std::string& error : errors) text += (text.empty() ? "" : "; ") + error;
  return text;
}

// The command's line on the served bus, for the engine, recorded under the console user.
Expected<std::unique_ptr<CommissionBus>, std::string> console_line(const BusActionSetup& setup,
                                                                  const CommissionTarget& target,
                                                                  const std::string& bus,
                                                                  const std::string& who) {
  std::optional<ServedBus> served = setup.served_bus(bus);
  if (!served) return Unexpected{fmt::format("the gateway no longer serves bus {}", bus)};
  auto line = std::make_unique<ServedBusLine>(std::move(*served), WriteOrigin{"console", who});
  auto opened = CommissionBus::on_served_line(target, std::move(line));
  if (!opened) return Unexpected{opened.error().message};
  return std::move(*opened);
}

}  // namespace

json BusActions::start_scan(const std::string& bus, const ScanRequest& request,
                            const std::string& who, unsigned& status) {
  if (setup_.config_path.empty()) {
    status = 409;
    return json{{"error", "the console scans the buses of a configuration file; this gateway "
                          "runs without one"}};
  }
  auto& scan = scans_[bus];
  if (scan) {
    const std::lock_guard lock(scan->mutex);
    if (scan->running) {
      status = 409;
      return json{{"error", fmt::format("a scan of {} is running", bus)}};
    }
  }
  ScanOptions options;
  if (request.from > 0 || request.to > 0) {
    options.from = request.from;
    if (request.to > 0) options.to = request.to;
  }
  BusOptions bus_options = console_bus_options(setup_.config_path, bus);
  auto prepared = prepare_scan(bus_options, options, setup_.families);
  if (!prepared) {
    status = 400;
    return json{{"error", joined(prepared.error())}};
  }
  scan = std::make_shared<Scan>();
  scan->running = true;
  spdlog::info("web console: {} scans bus {}", visible_text(who), visible_text(bus));
  asio::co_spawn(setup_.gateway_executor,
                 run_scan(scan, setup_, std::move(*prepared), bus, who), asio::detached);
  status = 202;
  return json{{"running", true}};
}

void BusActions::take(Scan& scan, const CommissionEvent& event) {
  const std::lock_guard lock(scan.mutex);
  if (const auto* progress = std::get_if<ProgressEvent>(&event)) {
    if (progress->total > 0) scan.progress = double(progress->done) / double(progress->total);
  } else if (const auto* finished = std::get_if<ScanFinishedEvent>(&event)) {
    scan.output += scan_result_text(*finished);
    scan.found = finished->tables;
  } else if (const auto* note = std::get_if<NoteEvent>(&event)) {
    scan.output += (note->warning ? "warning: " : "") + note->text + "\n";
  } else if (const auto* failed = std::get_if<FailedEvent>(&event)) {
    scan.output += failed->message + "\n";
    scan.error = failed->message.substr(0, failed->message.find('\n'));
  }
}

asio::awaitable<void> BusActions::run_scan(std::shared_ptr<Scan> scan, BusActionSetup setup,
                                           PreparedScan prepared, std::string bus,
                                           std::string who) {
  // Whatever happens to the scan, it ends: its bus is free for the next one, and a failure is
  // said once, in the log and in the scan's state.
  std::string failure;
  try {
    auto line = console_line(setup, prepared.bus, bus, who);
    if (!line) {
      failure = line.error();
    } else {
      const EventSink report = [scan](const CommissionEvent& event) { take(*scan, event); };
      const bool stopping = false;
      co_await setup.scan(**line, prepared, report, stopping);
    }
  } catch (const std::exception& e) {
    failure = fmt::format("the scan failed: {}", e.what());
    spdlog::error("web console: the scan of bus {} for {} failed: {}", visible_text(bus),
                  visible_text(who), e.what());
  }
  const std::lock_guard lock(scan->mutex);
  if (!failure.empty()) {
    scan->error = failure;
    scan->output += failure + "\n";
  }
  scan->progress = 1;
  scan->running = false;
}

json BusActions::scan_state(const std::string& bus) const {
  const auto found = scans_.find(bus);
  if (found == scans_.end() || !found->second)
    return json{{"running", false}, {"progress", 0}, {"output", ""}, {"found", json::array()},
                {"error", nullptr}};
  const Scan& scan = *found->second;
  const std::lock_guard lock(scan.mutex);
  json sensors = json::array();
  for (const SensorTable& sensor : scan.found)
    sensors.push_back(
        {{"address", sensor.address},
         {"model", sensor.model},
         {"serial", sensor.serial},
         {"firmware", sensor.firmware},
         {"config", sensor.text},
         {"configured_as",
          sensor.configured_as.empty() ? json(nullptr) : json(sensor.configured_as)},
         {"proposed_unit_id",
          sensor.proposed_unit_id == 0 ? json(nullptr) : json(sensor.proposed_unit_id)}});
  return json{{"running", scan.running},
              {"progress", scan.progress},
              {"output", scan.output},
              {"found", sensors},
              {"error", scan.error.empty() ? json(nullptr) : json(scan.error)}};
}

asio::awaitable<json> BusActions::raw(std::string bus, RawRequest request, std::string who,
                                      unsigned& status) {
  json reply{{"sent", nullptr}, {"received", nullptr}, {"verdict", ""}, {"decoded", ""},
             {"error", nullptr}, {"output", ""}};
  if (setup_.config_path.empty()) {
    status = 409;
    reply["error"] = "the console sends raw frames on the buses of a configuration file; this "
                     "gateway runs without one";
    co_return reply;
  }
  BusOptions options = console_bus_options(setup_.config_path, bus);
  options.addresses = {request.address};
  options.driver_optional = true;  // the request is built here: no device profile needed
  const auto target = resolve_bus_options(options, setup_.families);
  if (!target) {
    status = 400;
    reply["error"] = joined(target.error());
    co_return reply;
  }
  spdlog::info("web console: {} sends function {} to address {} on bus {}", visible_text(who),
               request.function, request.address, visible_text(bus));
  // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
  auto exchange = [&]() -> asio::awaitable<int> {
    auto line = console_line(setup_, *target, bus, who);
    if (!line) {
      reply["error"] = line.error();
      co_return 1;
    }
    const EventSink report = [&reply](const CommissionEvent& event) {
      if (const auto* exchanged = std::get_if<ExchangeEvent>(&event)) {
        reply["sent"] = hex_bytes(exchanged->sent);
        if (exchanged->answered) reply["received"] = hex_bytes(exchanged->received);
        reply["verdict"] = received_verdict(*exchanged);
        if (exchanged->answered) reply["decoded"] = exchanged->decoded + "\n";
        reply["output"] = reply["output"].get<std::string>() + exchange_text(*exchanged);
      } else if (const auto* failed = std::get_if<FailedEvent>(&event)) {
        reply["error"] = failed->message;
        reply["output"] = reply["output"].get<std::string>() + failed->message + "\n";
      }
    };
    const RawOptions raw{request.function, request.data};
    const bool stopping = false;
    co_return co_await raw_exchange(**line, raw, setup_.commands, report, stopping);
  };
  int exit_code = 1;
  try {
    exit_code = co_await asio::co_spawn(setup_.gateway_executor, std::move(exchange),
                                        asio::use_awaitable);
  } catch (const std::exception& e) {
    spdlog::error("web console: a raw frame on bus {} for {} failed: {}", visible_text(bus),
                  visible_text(who), e.what());
    reply["error"] = fmt::format("the request failed: {}", e.what());
  }
  status = exit_code == 2 ? 400 : 200;
  co_return reply;
}

}  // namespace tiltgate
