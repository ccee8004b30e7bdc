// A small plant for end-to-end tests: two H6 (units 1 and 2, "boom-left" at address 223 and
// "boom-right" at 224) and an H4360 (unit 3, "mast" at 101) on one simulated Rieker bus
// "line1", served by build/tiltgate on a free loopback port.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <string>

#include "e2e/support/gateway_process.h"
#include "e2e/support/simulator_thread.h"

namespace tiltgate::test {

struct Plant {
  // Starts the simulator and the gateway, and waits until the gateway listens. `more_config`
  // is appended to its config file (e.g. an [http] table).
  explicit Plant(bool writes = true, int max_clients = 40, const std::string& more_config = "");

  // Polls until unit's angles are readable (the first polls take a moment).
  bool wait_online(int unit, std::chrono::seconds limit = std::chrono::seconds(10));

  TempDir dir;
  std::uint16_t port = free_tcp_port();
  std::unique_ptr<SimulatorThread> sim;
  std::unique_ptr<GatewayProcess> gateway;
};

}  // namespace tiltgate::test
