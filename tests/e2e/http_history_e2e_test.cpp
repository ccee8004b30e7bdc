// The gateway samples every sensor's angles into its history once a second (the [http]
// default): the demo's history endpoints fill up in time order, as JSON and as a CSV download,
// and the status page is served at /.
#include <doctest/doctest.h>

#include <chrono>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/gateway_process.h"
#include "e2e/support/http_client.h"
#include "e2e/support/http_demo.h"

using namespace tiltgate::test;
using namespace std::chrono_literals;

namespace {

std::vector<long long> sample_times(const std::string& json) {
  std::vector<long long> times;
  const std::regex sample(R"re(\{"t":(\d+),"x":(-?[0-9.e-]+|null),"y":(-?[0-9.e-]+|null)\})re");
  for (auto it = std::sregex_iterator(json.begin(), json.end(), sample);
       it != std::sregex_iterator(); ++it)
    times.push_back(std::stoll((*it)[1]));
  return times;
}

}  // namespace

TEST_CASE("HTTP: the demo keeps each sensor's angle history and serves it as JSON and CSV") {
  HttpDemo started;
  GatewayProcess& demo = started.process;
  const std::uint16_t http_port = started.http_port;

  const Response page = get(http_port, "/");
  CHECK(page.status == 200);
  CHECK(page.headers.at("content-type") == "text/html; charset=utf-8");
  CHECK(page.body.find("<!doctype html>") == 0);

  // One sample a second: three take about three seconds; allow far more on a busy machine.
  std::string history;
  const auto deadline = std::chrono::steady_clock::now() + 30s;
  while (std::chrono::steady_clock::now() < deadline) {
    history = get(http_port, "/api/sensors/boom-left/history").body;
    if (sample_times(history).size() >= 3 && history.find("\"x\":null") == std::string::npos)
      break;
    std::this_thread::sleep_for(200ms);
  }
  const std::vector<long long> times = sample_times(history);
  REQUIRE_MESSAGE(times.size() >= 3, history);
  for (std::size_t i = 1; i < times.size(); ++i) CHECK(times[i] > times[i - 1]);
  CHECK(history.front() == '[');
  CHECK(history.back() == ']');

  const Response csv = get(http_port, "/api/sensors/boom-left/history.csv");
  CHECK(csv.status == 200);
  CHECK(csv.headers.at("content-type") == "text/csv; charset=utf-8");
  CHECK(csv.headers.at("content-disposition") == "attachment; filename=\"boom-left-history.csv\"");
  CHECK(csv.body.starts_with("time_utc,unix_ms,x_deg,y_deg\r\n"));
  CHECK(std::regex_search(csv.body, std::regex(R"(\r\n\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z,\d+,-?[0-9.]+,-?[0-9.]+\r\n)")));

  CHECK(get(http_port, "/api/sensors/nobody/history").status == 404);
  CHECK(demo.terminate() == 0);
}
