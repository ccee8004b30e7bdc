// One shared RS485 line of simulated sensors served by build/tiltgate with every bus and sensor
// timing key at its default (poll_ms 100, timeout_ms 50, retries 2, max_timeout_ms 500,
// stale_ms 1 s) and writes on, for the tests of what one failing sensor may cost the others:
// Rieker H6 at addresses 11, 12, ... (units 1, 2, ...) on a line paced at its baud, or Dyna
// modules 1, 2, ... on a Spectron line. The simulator runs in the test process
// (tests/e2e/support/simulator_thread.h), so a test can make any sensor fail.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/simulator_thread.h"

namespace tiltgate::test {

template <class SimulatorThreadType>
struct SharedLinePlant {
  // `sim_options` with its link path set here; `bus_keys` and `sensor_keys(unit)` as the bus
  // and each sensor need them (protocol, baud; model keys), every timing key left out. Waits
  // until every unit but `never_fresh` reads fresh.
  template <class Options, class SensorKeys>
  SharedLinePlant(Options sim_options, int sensor_count, const std::string& bus_keys,
                  const std::string& model, SensorKeys sensor_keys, int first_address,
                  const std::vector<int>& never_fresh = {})
      : count(sensor_count) {
    sim_options.link_path = (dir.path() / "ttyRS485").string();
    sim = std::make_unique<SimulatorThreadType>(sim_options);
    std::string text = server_table(port, "writes = true") +
                       bus_table("line1", sim_options.link_path, bus_keys);
    for (int unit = 1; unit <= count; ++unit)
      text += sensor_table(fmt::format("s{}", unit), "line1", model, first_address + unit - 1,
                           unit, sensor_keys(unit));
    const auto config = dir.write("plant.toml", text);
    gateway = std::make_unique<GatewayProcess>(
        std::vector<std::string>{"run", "--config", config.string()}, dir.path());
    REQUIRE_MESSAGE(gateway->wait_listening(port), gateway->log());
    for (int unit : units_but(never_fresh))
      REQUIRE_MESSAGE(wait_fresh(unit), "unit ", unit, " never read: ", gateway->log());
    // The start-up pass reads each sensor's identity before its first poll, four exchanges a
    // sensor: on a slow line of ten its first sensor's first reading is near its stale_ms old
    // when its second comes. The tests judge the line from the first round of plain polls on.
    const auto all_fresh = std::chrono::steady_clock::now();
    for (int unit : units_but(never_fresh))
      REQUIRE_MESSAGE(wait_read_since(unit, all_fresh), "unit ", unit,
                      " not polled again: ", gateway->log());
  }

  // Until the unit's angle reads and its status says online and fresh.
  bool wait_fresh(int unit, std::chrono::seconds limit = std::chrono::seconds(15)) {
    ModbusClient client(port, unit);
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
      const auto status = client.input(6, 1);
      if (!client.input(0, 2).empty() && status.size() == 1 && (status[0] & 0x03) == 0x01)
        return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  // Until the unit holds a reading taken after `since` (its age, input register 7, says when).
  bool wait_read_since(int unit, std::chrono::steady_clock::time_point since,
                       std::chrono::seconds limit = std::chrono::seconds(15)) {
    ModbusClient client(port, unit);
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
      const auto age = client.input(7, 1);
      const auto now = std::chrono::steady_clock::now();
      if (age.size() == 1 && age[0] != 65535 && now - std::chrono::milliseconds(age[0]) > since)
        return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  // Every unit but `sick`.
  std::vector<int> units_but(std::vector<int> sick) const {
    std::vector<int> units;
    for (int unit = 1; unit <= count; ++unit)
      if (std::find(sick.begin(), sick.end(), unit) == sick.end()) units.push_back(unit);
    return units;
  }

  TempDir dir;
  int count;
  std::uint16_t port = free_tcp_port();
  std::unique_ptr<SimulatorThreadType> sim;
  std::unique_ptr<GatewayProcess> gateway;
};

}  // namespace tiltgate::test
