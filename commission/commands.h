// The subcommands of the tiltgate executable. Each returns the process exit code.
#pragma once

#include <cstdint>
#include <string>

#include "driver/family.h"
#include "driver/family_commands.h"
#include "commission/commission_options.h"
#include "commission/scan_plan.h"
#include "commission/set_plan.h"

namespace tiltgate {

int check_command(const std::string& config_path, FamilyList families);
int map_command(const std::string& config_path, const std::string& format, FamilyList families);
int run_command(const std::string& config_path, FamilyList families);

struct DemoOptions {
  std::string listen = "127.0.0.1";
  std::uint16_t port = 1502;
  std::uint16_t http_port = 8080;  // the HTTP status API and metrics, on `listen`; 0: off
  std::string mqtt_host;           // the MQTT feed's broker, under tiltgate/demo/; empty: off
  std::uint16_t mqtt_port = 1883;
};
// The demo serves each family of `commands` that has demo sensors.
int demo_command(const DemoOptions& options, FamilyCommandsList commands);

// `tiltgate sim FAMILY`: the family's simulator on a pseudo-terminal until SIGINT/SIGTERM.
int sim_command(const FamilyCommands& family, const SimulatorSetup& setup);

// Commissioning (docs/commissioning.md, "Commissioning"): exit 0 on success, 1 when a sensor does not answer
// or the tty cannot be used, 2 on a usage error.
// `tiltgate info`: each sensor's identity, lock level and angles.
int info_command(const BusOptions& bus, FamilyList families);

struct WatchOptions {
  int count = 0;  // rounds before stopping; 0: until SIGINT/SIGTERM
  int interval_ms = 500;
  std::string log;  // CSV file every reading is appended to; empty: none
};
// `tiltgate watch`: every sensor polled in turn, one row each, until stopped or `count` rounds.
int watch_command(const BusOptions& bus, const WatchOptions& options, FamilyList families);

// `tiltgate scan`: every address of a range probed, one row per sensor that answered.
int scan_command(const BusOptions& bus, const ScanOptions& options, FamilyList families);
// `tiltgate set`: one setting of one sensor, then its state read back.
// `commands`: the families' set helpers.
int set_command(const BusOptions& bus, const SetArguments& arguments, FamilyList families,
                FamilyCommandsList commands);

struct RawOptions {
  std::int64_t function = 0;
  std::string data;  // hex bytes; empty: none
};
// `tiltgate raw`: one request by function number, the bytes each way and the reply decoded.
// `commands`: the families' raw request builders.
int raw_command(const BusOptions& bus, const RawOptions& raw, FamilyList families,
                FamilyCommandsList commands);

}  // namespace tiltgate
