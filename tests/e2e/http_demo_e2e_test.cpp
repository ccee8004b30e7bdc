// `tiltgate demo --http-port N`: the status API shows every demo sensor with a live angle, and
// /metrics has an angle series for each.
#include <doctest/doctest.h>

#include <chrono>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/gateway_process.h"
#include "e2e/support/http_client.h"
#include "e2e/support/http_demo.h"
#include "driver/family_commands.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;

TEST_CASE("HTTP: the demo serves every sensor's angles in the API and the metrics") {
  HttpDemo started;
  GatewayProcess& demo = started.process;
  const std::uint16_t http_port = started.http_port;
  std::vector<std::string> names;
  for (const FamilyCommands* family : registered_family_commands())
    for (const DemoSensor& sensor : family->demo.sensors) names.push_back(std::string(sensor.name));
  REQUIRE(names.size() > 1);

  // Every sensor online with an X angle (the first polls take a moment).
  std::string sensors;
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  auto all_online = [&] {
    for (const std::string& name : names) {
      const std::string one = get(http_port, "/api/sensors/" + name).body;
      if (one.find("\"online\":true") == std::string::npos ||
          one.find("\"x\":null") != std::string::npos)
        return false;
    }
    return true;
  };
  while (!all_online() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(100ms);
  REQUIRE_MESSAGE(all_online(), demo.log());

  const Response list = get(http_port, "/api/sensors");
  const Response metrics = get(http_port, "/metrics");
  for (const std::string& name : names) {
    INFO(name);
    CHECK(list.body.find("{\"name\":\"" + name + "\"") != std::string::npos);
    CHECK(metrics.body.find("tiltgate_angle_degrees{sensor=\"" + name + "\"") != std::string::npos);
  }
  CHECK(demo.terminate() == 0);
}
