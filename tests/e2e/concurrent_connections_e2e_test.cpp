// A write waits for its sensor, and only its own connection waits with it: reads on another
// connection are answered from the cache meanwhile (docs/operations.md, "How the gateway behaves").
#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "e2e/support/gateway_config.h"
#include "e2e/support/gateway_process.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/simulator_thread.h"
#include "rieker/simulator.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

TEST_CASE("a read on another connection is answered while a write waits on a silent sensor") {
  TempDir dir;
  rieker::RiekerSimulatorOptions live;
  rieker::SimulatedSensorOptions h6;
  h6.model = rieker::Model::h6;
  h6.address = 223;
  h6.angle_x = 1.5;
  live.sensors = {h6};
  live.link_path = (dir.path() / "ttyLive").string();
  SimulatorThread live_bus(live);
  rieker::RiekerSimulatorOptions silent;  // a line where no sensor answers
  silent.link_path = (dir.path() / "ttySilent").string();
  SimulatorThread silent_bus(silent);

  const std::uint16_t port = free_tcp_port();
  // Each transaction on line2 waits 5 s for a reply that never comes: the write to unit 2
  // takes at least that long, long after the reads below are answered.
  const auto config = dir.write(
      "plant.toml", server_table(port, "writes = true\nwrite_timeout_ms = 60000") +
                        bus_table("line1", live.link_path, "timeout_ms = 100") +
                        bus_table("line2", silent.link_path, "timeout_ms = 5000\nretries = 0") +
                        sensor_table("boom", "line1", "h6", 223, 1, "poll_ms = 50") +
                        sensor_table("ghost", "line2", "h6", 225, 2));
  GatewayProcess gateway({"run", "--config", config.string()}, dir.path());
  REQUIRE_MESSAGE(gateway.wait_listening(port), gateway.log());
  ModbusClient reader(port, 1);
  bool online = false;
  for (int i = 0; i < 200 && !online; ++i) {
    online = reader.input(0, 2).size() == 2;
    if (!online) std::this_thread::sleep_for(50ms);
  }
  REQUIRE_MESSAGE(online, gateway.log());

  std::atomic<bool> write_answered{false};
  std::thread writer([&] {
    ModbusClient client(port, 2);
    modbus_set_response_timeout(client.raw(), 120, 0);
    client.write(0, 2);  // the filter of the silent sensor
    write_answered = true;
  });
  std::this_thread::sleep_for(300ms);  // lets the write reach the gateway first
  int answered = 0;
  for (int i = 0; i < 10; ++i) answered += reader.input(0, 2).size() == 2 ? 1 : 0;
  CHECK(answered == 10);
  CHECK_FALSE(write_answered);  // still waiting for the silent sensor
  writer.join();
  CHECK(write_answered);
  CHECK(gateway.running());
}
