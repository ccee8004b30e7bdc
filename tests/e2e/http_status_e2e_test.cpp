// build/tiltgate run with [http] on a free loopback port, read over real TCP sockets with a
// minimal HTTP/1.1 client: the JSON API, /metrics parsed strictly, 404 and 405, and a client
// that sends half a request dropped while another is served.
#include <doctest/doctest.h>

#include <unistd.h>

#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "e2e/support/gateway_config.h"
#include "e2e/support/http_client.h"
#include "e2e/support/modbus_client.h"
#include "e2e/support/plant.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

struct HttpPlant {
  HttpPlant()
      : http_port(free_tcp_port()),
        plant(true, 40, http_table(http_port)) {
    REQUIRE_MESSAGE(plant.gateway->wait_listening(http_port), plant.gateway->log());
    for (int unit = 1; unit <= 3; ++unit) REQUIRE(plant.wait_online(unit));
  }
  std::uint16_t http_port;
  Plant plant;
};

}  // namespace

TEST_CASE("HTTP: /healthz, the sensors and buses as JSON, one sensor by name") {
  HttpPlant p;
  const Response health = get(p.http_port, "/healthz");
  CHECK(health.status == 200);
  CHECK(health.body == "ok\n");

  const Response sensors = get(p.http_port, "/api/sensors");
  CHECK(sensors.status == 200);
  CHECK(sensors.headers.at("content-type") == "application/json");
  const std::string& all = sensors.body;
  CHECK(all.starts_with("[{\"name\":\"boom-left\",\"bus\":\"line1\",\"unit_id\":1,\"address\":223,"));
  CHECK(all.find("\"serial\":\"962285\"") != std::string::npos);
  CHECK(all.find("\"online\":true,\"stale\":false,\"x\":1.5,\"y\":-2.25,") != std::string::npos);
  CHECK(all.find("{\"name\":\"boom-right\"") != std::string::npos);
  CHECK(all.find("\"x\":10,\"y\":20,") != std::string::npos);

  const Response mast = get(p.http_port, "/api/sensors/mast");
  CHECK(mast.status == 200);
  CHECK(mast.body.starts_with("{\"name\":\"mast\",\"bus\":\"line1\",\"unit_id\":3,\"address\":101,"));
  CHECK(mast.body.find("\"x\":-30.5,") != std::string::npos);

  const Response buses = get(p.http_port, "/api/buses");
  CHECK(buses.status == 200);
  CHECK(buses.body.starts_with("[{\"name\":\"line1\",\"port\":"));
  CHECK(buses.body.find("\"baud\":125000,\"protocol\":\"rieker\",\"polls\":") != std::string::npos);

  CHECK(get(p.http_port, "/api/sensors/nobody").status == 404);
  CHECK(get(p.http_port, "/index.php").status == 404);
  const Response post = request(p.http_port, "POST", "/api/sensors");
  CHECK(post.status == 405);
  CHECK(post.headers.at("allow") == "GET, HEAD");
  CHECK(request(p.http_port, "DELETE", "/api/sensors/mast").status == 405);
}

TEST_CASE("HTTP: /metrics is strict Prometheus text with each sensor's series") {
  HttpPlant p;
  // One request answered with an exception: input register 60000 is mapped by no sensor.
  ModbusClient client(p.plant.port, 1);
  CHECK(client.input(60000, 1).empty());
  const Response metrics = get(p.http_port, "/metrics");
  REQUIRE(metrics.status == 200);
  CHECK(metrics.headers.at("content-type") == "text/plain; version=0.0.4; charset=utf-8");
  // Text format 0.0.4: HELP and TYPE once per metric, before its samples; each sample
  // `name{label="value",...} value` with escaped label values.
  const std::regex help(R"(# HELP ([a-zA-Z_:][a-zA-Z0-9_:]*) .*)");
  const std::regex type(R"(# TYPE ([a-zA-Z_:][a-zA-Z0-9_:]*) (counter|gauge|histogram|summary|untyped))");
  const std::regex sample(
      R"(([a-zA-Z_:][a-zA-Z0-9_:]*)(\{[a-zA-Z_][a-zA-Z0-9_]*="(?:[^"\\\n]|\\[\\"n])*")"
      R"((?:,[a-zA-Z_][a-zA-Z0-9_]*="(?:[^"\\\n]|\\[\\"n])*")*\})? )"
      R"((-?[0-9]+(?:\.[0-9]+)?(?:e[-+]?[0-9]+)?|NaN|[+-]Inf))");
  std::set<std::string> helped, typed, histograms;
  std::map<std::string, std::string> samples;  // series -> value
  // A histogram's samples are its name with _bucket (labelled le), _sum and _count.
  const auto family_of = [&](const std::string& name) {
    for (const char* suffix : {"_bucket", "_sum", "_count"}) {
      const std::string_view end(suffix);
      if (name.ends_with(end)) {
        const std::string family = name.substr(0, name.size() - end.size());
        if (histograms.count(family) == 1) return family;
      }
    }
    return name;
  };
  std::istringstream lines(metrics.body);
  std::string line;
  while (std::getline(lines, line)) {
    INFO(line);
    std::smatch m;
    if (std::regex_match(line, m, help)) {
      CHECK(helped.insert(m[1]).second);
    } else if (std::regex_match(line, m, type)) {
      CHECK(helped.count(m[1]) == 1);
      CHECK(typed.insert(m[1]).second);
      if (m[2] == "counter") CHECK(std::string(m[1]).ends_with("_total"));
      if (m[2] == "histogram") histograms.insert(m[1]);
    } else {
      REQUIRE(std::regex_match(line, m, sample));
      CHECK(typed.count(family_of(m[1])) == 1);
      samples[std::string(m[1]) + std::string(m[2])] = m[3];
    }
  }
  const std::string left = R"(sensor="boom-left",bus="line1",unit="1")";
  CHECK(samples["tiltgate_angle_degrees{" + left + ",axis=\"x\"}"] == "1.5");
  CHECK(samples["tiltgate_angle_degrees{" + left + ",axis=\"y\"}"] == "-2.25");
  CHECK(samples["tiltgate_sensor_online{" + left + "}"] == "1");
  CHECK(samples.count("tiltgate_reading_age_seconds{" + left + "}") == 1);
  CHECK(std::stoul(samples["tiltgate_polls_total{" + left + ",result=\"ok\"}"]) > 0);
  CHECK(samples.count("tiltgate_polls_total{" + left + ",result=\"failed\"}") == 1);
  CHECK(std::stoul(samples["tiltgate_bus_polls_total{bus=\"line1\"}"]) > 0);
  // Every reply in the histogram: its +Inf bucket is its count, and there were replies.
  const std::string replies = samples["tiltgate_sensor_reply_seconds_count{" + left + "}"];
  CHECK(std::stoul(replies) > 0);
  CHECK(samples["tiltgate_sensor_reply_seconds_bucket{" + left + ",le=\"+Inf\"}"] == replies);
  CHECK(std::stod(samples["tiltgate_process_start_time_seconds"]) > 1.6e9);
  // The plant read every unit's angles with function 04 before this, and one 04 failed.
  CHECK(std::stoul(samples["tiltgate_modbus_requests_total{function=\"04\"}"]) >= 4);
  CHECK(samples["tiltgate_modbus_exceptions_total{function=\"04\",code=\"02\"}"] == "1");
  CHECK(std::stoul(samples["tiltgate_modbus_connections_total"]) >= 4);
  CHECK(samples["tiltgate_sensor_failures_total{" + left + ",reason=\"timeout\"}"] == "0");
  CHECK(std::stod(samples["tiltgate_bus_busy_seconds_total{bus=\"line1\"}"]) > 0);
}

TEST_CASE("HTTP: polls per second and the bus's use of the wire after a few seconds") {
  HttpPlant p;
  // Rates need two samples a second apart; the gateway samples once a second.
  std::string buses;
  for (int i = 0; i < 50; ++i) {
    buses = get(p.http_port, "/api/buses").body;
    if (buses.find("\"utilisation\":null") == std::string::npos) break;
    usleep(100'000);
  }
  INFO(buses);
  const std::smatch m = [&] {
    std::smatch found;
    std::regex_search(buses, found,
                      std::regex(R"("polls_per_s":([0-9.e+-]+),"utilisation":([0-9.e+-]+))"));
    return found;
  }();
  REQUIRE(m.size() == 3);
  // Three sensors polled every 40 ms on a simulated 125000-baud line: polls run, the wire is
  // partly used, never more than all of it.
  CHECK(std::stod(m[1]) > 5);
  CHECK(std::stod(m[2]) > 0);
  CHECK(std::stod(m[2]) <= 1);
  const std::string sensors = get(p.http_port, "/api/sensors").body;
  CHECK(std::regex_search(sensors, std::regex(R"("polls_per_s":[0-9])")));
  CHECK(sensors.find("\"failures\":{\"timeout\":") != std::string::npos);
}

TEST_CASE("HTTP: a client that sends half a request is dropped, and others are served meanwhile") {
  HttpPlant p;
  const int half = connect_to(p.http_port);
  send_all(half, "GET /healthz HTTP/1.1\r\nHost: local");
  // Served at once although the half request waits.
  const Response other = get(p.http_port, "/healthz");
  CHECK(other.status == 200);
  // The server closes the half request (after its 5 s request time-out), answering nothing;
  // the socket's own 30 s limit only keeps a broken server from hanging the test.
  bool timed_out = false;
  const std::string answer = read_to_close(half, &timed_out);
  ::close(half);
  CHECK_FALSE(timed_out);
  CHECK(answer.empty());
  // And the gateway serves on.
  CHECK(get(p.http_port, "/healthz").status == 200);
}

TEST_CASE("HTTP: an oversized request is refused and closed") {
  HttpPlant p;
  const int fd = connect_to(p.http_port);
  send_all(fd, "GET /healthz HTTP/1.1\r\nHost: localhost\r\nX-Filler: " + std::string(20000, 'a') +
                   "\r\n\r\n");
  bool timed_out = false;
  const std::string raw = read_to_close(fd, &timed_out);
  ::close(fd);
  CHECK_FALSE(timed_out);
  CHECK(parse_response(raw).status == 413);
}
