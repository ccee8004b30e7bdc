// The read-only HTTP routes over a fixed GatewayStatus: which endpoints exist, what each
// answers, and that a health check takes no copy of the status.
#include <doctest/doctest.h>

#include <cmath>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "http/http_routes.h"
#include "status/json_values.h"
#include "status/status_json.h"
#include "status/status_metrics.h"
#include "unit/status/status_fixture.h"

using namespace tiltgate;
using namespace tiltgate::test;

TEST_CASE("HTTP routes: read-only, known endpoints only, unknown sensors 404") {
  int taken = 0;
  const StatusSource status = [&] {
    ++taken;
    return plant();
  };
  CHECK(route_http("GET", "/healthz", status).body == "ok\n");
  CHECK(taken == 0);  // a health check does not copy the status
  const HttpReply post = route_http("POST", "/api/sensors", status);
  CHECK(post.status == 405);
  CHECK(post.allow_get);
  CHECK(route_http("PUT", "/healthz", status).status == 405);
  CHECK(route_http("GET", "/nothing", status).status == 404);
  CHECK(route_http("GET", "/api/sensors/nobody", status).status == 404);
  const HttpReply one = route_http("GET", "/api/sensors/boom?x=1", status);
  CHECK(one.status == 200);
  CHECK(one.content_type == "application/json");
  CHECK(one.body == sensor_json(boom()));
  CHECK(route_http("GET", "/api/sensors/m%61st", status).body == sensor_json(silent("mast")));
  CHECK(route_http("GET", "/api/sensors/m%6", status).status == 404);
  CHECK(route_http("GET", "/api/buses", status).body == buses_json(plant().buses));
  const HttpReply state = route_http("GET", "/api/status", status);
  CHECK(state.status == 200);
  CHECK(state.content_type == "application/json");
  CHECK(state.body.starts_with(R"({"role":"active","redundancy":null,"uptime_s":)"));
  CHECK(route_http("POST", "/api/status", status).status == 405);
  const HttpReply metrics = route_http("GET", "/metrics", status);
  CHECK(metrics.content_type == kMetricsContentType);
  CHECK(metrics.body == metrics_text(plant()));
}
