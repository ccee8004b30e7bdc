// A bus's scan and raw frames from the web console (admin), run by the commissioning engine in
// the gateway itself (commission/scan_engine.h, commission/raw_engine.h) on a command's line of
// the served bus (control/served_bus_line.h): their transactions take the line's spare time, as
// an engineer's command through the control socket does, and what they change is recorded in
// the audit trail under the console user. The engine reports events; this turns them into the
// JSON of docs/web-console.md. One scan per bus at a time; its progress, output and results are
// kept until the next one starts, so a page that reloads finds them.
//
// Threads: called on the HTTP server's thread; the engine runs on the buses' executor, and a
// scan's state is shared between the two under its mutex.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "commission/scan_engine.h"
#include "console/console_requests.h"
#include "control/served_bus_line.h"
#include "driver/family_commands.h"

namespace tiltgate {

// What the console's commands need to run.
struct BusActionSetup {
  std::string config_path;  // the served file, whose [[bus]] and [[sensor]] tables they read
  boost::asio::any_io_executor gateway_executor;  // the buses'
  // The bus of that name as the gateway serves it now; called on the buses' executor.
  std::function<std::optional<ServedBus>(const std::string&)> served_bus;
  FamilyList families;
  FamilyCommandsList commands;
  // The scan's work on its bus: the engine's (scan_bus); a test's may fail on purpose.
  std::function<boost::asio::awaitable<int>(CommissionBus&, const PreparedScan&,
                                            const EventSink&, const bool&)>
      scan = scan_bus;
};

class BusActions {
 public:
  explicit BusActions(BusActionSetup setup) : setup_(std::move(setup)) {}

  // POST /api/buses/NAME/scan: 202, 400 for a request the bus cannot take, or 409 while one
  // runs; `who` names the console user in the audit trail.
  nlohmann::json start_scan(const std::string& bus, const ScanRequest& request,
                            const std::string& who, unsigned& status);
  // GET /api/buses/NAME/scan.
  nlohmann::json scan_state(const std::string& bus) const;
  // POST /api/buses/NAME/raw: the bytes each way, the checksum's verdict, the reply decoded.
  boost::asio::awaitable<nlohmann::json> raw(std::string bus, RawRequest request, std::string who,
                                             unsigned& status);

 private:
  struct Scan {
    mutable std::mutex mutex;
    bool running = false;
    double progress = 0;
    std::string output;
    std::vector<SensorTable> found;
    std::string error;
  };
  static void take(Scan& scan, const CommissionEvent& event);
  static boost::asio::awaitable<void> run_scan(std::shared_ptr<Scan> scan, BusActionSetup setup,
                                               PreparedScan prepared, std::string bus,
                                               std::string who);

  BusActionSetup setup_;
  std::map<std::string, std::shared_ptr<Scan>> scans_;  // the HTTP thread's
};

}  // namespace tiltgate
