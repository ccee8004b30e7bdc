// A bus's scan and raw frames from the web console (admin), each run as `tiltgate scan|raw
// --via-gateway` through the gateway's own control socket (console/child_command.h), on behalf
// of the console user, who the audit trail names. One scan per bus at a time; its progress,
// output and results are kept until the next one starts, so a page that reloads finds them.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "console/console_requests.h"

namespace tiltgate {

struct ScanFound {
  std::int64_t address = 0;
  std::string model, serial, firmware;
  std::string config;  // its [[sensor]] table, as `scan --config-out` writes it
};

// The sensors in a configuration `scan --config-out` wrote, each with its own table's text.
std::vector<ScanFound> found_in_scan_config(const std::string& text);

// What the console's commands need to know to run: the served file and the control socket.
struct BusActionSetup {
  std::string config_path;
  std::string control_socket;  // empty: [server] control_socket is off
};

class BusActions {
 public:
  BusActions(boost::asio::any_io_executor executor, BusActionSetup setup)
      : executor_(std::move(executor)), setup_(std::move(setup)) {}

  // POST /api/buses/NAME/scan: 202, or 409 while one runs; `who` for the audit trail.
  nlohmann::json start_scan(const std::string& bus, const ScanRequest& request,
                            const std::string& who, unsigned& status);
  // GET /api/buses/NAME/scan.
  nlohmann::json scan_state(const std::string& bus) const;
  // POST /api/buses/NAME/raw: the bytes each way, the checksum's verdict, the reply decoded.
  boost::asio::awaitable<nlohmann::json> raw(std::string bus, RawRequest request, std::string who,
                                             unsigned& status);

 private:
  struct Scan {
    bool running = false;
    double progress = 0;
    std::string output;
    std::vector<ScanFound> found;
    std::string error;
  };
  std::vector<std::string> common_args(const std::string& command, const std::string& bus,
                                       const std::string& who) const;
  boost::asio::awaitable<void> run_scan(std::shared_ptr<Scan> scan, std::vector<std::string> args,
                                        std::string config_out);

  boost::asio::any_io_executor executor_;
  BusActionSetup setup_;
  std::map<std::string, std::shared_ptr<Scan>> scans_;
};

}  // namespace tiltgate
