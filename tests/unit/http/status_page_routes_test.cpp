// The status page at / and the per-sensor history endpoints: the page is self-contained (its
// markup, script and style sheet all from the gateway, nothing inline, nothing from another
// host), the history comes as JSON and as a CSV download, and an unknown sensor is a 404 like
// everywhere else in the API.
#include <doctest/doctest.h>

#include <regex>
#include <string>
#include <vector>

#include "status/history_format.h"
#include "status/history_recorder.h"
#include "http/http_routes.h"

using namespace tiltgate;

namespace {

GatewayStatus no_sensors() { return {}; }

const std::vector<AngleSample> kBoomHistory{{1764638738250, 1.25f, -0.5f},
                                            {1764638739250, std::nullopt, std::nullopt}};

std::optional<std::vector<AngleSample>> boom_history(std::string_view name) {
  if (name == "boom") return kBoomHistory;
  if (name == "mast") return std::vector<AngleSample>{};
  return std::nullopt;
}

SensorStatus sensor(std::string name, bool stale, std::optional<double> x,
                    std::optional<double> y) {
  SensorStatus s;
  s.name = std::move(name);
  s.online = true;
  s.stale = stale;
  s.x = x;
  s.y = y;
  return s;
}

}  // namespace

TEST_CASE("status page: / is an HTML page that loads nothing from another host") {
  const HttpReply page = route_http("GET", "/", no_sensors);
  CHECK(page.status == 200);
  CHECK(page.content_type == "text/html; charset=utf-8");
  CHECK(page.body.starts_with("<!doctype html>"));
  CHECK(page.body.find("<meta name=\"viewport\"") != std::string::npos);
  const HttpReply script = route_http("GET", "/status_page.js", no_sensors);
  CHECK(script.status == 200);
  CHECK(script.content_type == "text/javascript; charset=utf-8");
  const HttpReply style = route_http("GET", "/status_page.css", no_sensors);
  CHECK(style.status == 200);
  CHECK(style.content_type == "text/css; charset=utf-8");
  const HttpReply forms = route_http("GET", "/config_forms.js", no_sensors);
  CHECK(forms.status == 200);
  CHECK(forms.content_type == "text/javascript; charset=utf-8");
  const HttpReply traffic = route_http("GET", "/traffic_view.js", no_sensors);
  CHECK(traffic.status == 200);
  CHECK(traffic.content_type == "text/javascript; charset=utf-8");
  for (const std::string& body : {page.body, script.body, style.body, forms.body, traffic.body}) {
    // Self-contained: no absolute URL at all (a script, style sheet, font or image from a CDN
    // would need one), and no protocol-relative one in src/href either.
    CHECK(body.find("http://") == std::string::npos);
    CHECK(body.find("https://") == std::string::npos);
    CHECK_FALSE(std::regex_search(body, std::regex(R"((src|href)\s*=\s*["']//)")));
    CHECK_FALSE(std::regex_search(body, std::regex(R"(@import|url\()")));
  }
  // It reads the JSON API the gateway serves, by relative path.
  CHECK(script.body.find("\"/api/sensors\"") != std::string::npos);
  CHECK(script.body.find("\"/api/buses\"") != std::string::npos);
  CHECK(script.body.find("/history") != std::string::npos);
  CHECK(route_http("HEAD", "/", no_sensors).status == 200);
  CHECK(route_http("POST", "/", no_sensors).status == 405);
}

// The Content-Security-Policy (http/http_response.h) allows scripts and styles from the
// gateway's files only: an inline one would not run in the browser.
TEST_CASE("status page: no inline script, style, style attribute or event handler") {
  const std::string page = route_http("GET", "/", no_sensors).body;
  const std::string script = route_http("GET", "/status_page.js", no_sensors).body;
  const std::string forms = route_http("GET", "/config_forms.js", no_sensors).body;
  const std::string traffic = route_http("GET", "/traffic_view.js", no_sensors).body;
  CHECK(page.find("<script src=\"/status_page.js\"></script>") != std::string::npos);
  CHECK(page.find("<script src=\"/config_forms.js\"></script>") != std::string::npos);
  CHECK(page.find("<script src=\"/traffic_view.js\"></script>") != std::string::npos);
  CHECK(page.find("<link rel=\"stylesheet\" href=\"/status_page.css\">") != std::string::npos);
  CHECK_FALSE(std::regex_search(page, std::regex(R"(<script(?![^>]*\bsrc=)[^>]*>)")));
  for (const std::string& markup : {page, script, forms, traffic}) {  // the scripts make markup too
    CHECK(markup.find("<style") == std::string::npos);
    CHECK_FALSE(std::regex_search(markup, std::regex(R"(\sstyle\s*=\s*["'])")));
    CHECK_FALSE(std::regex_search(markup, std::regex(R"(<[^>]*\son[a-z]+\s*=)")));
    CHECK(markup.find("javascript:") == std::string::npos);
  }
}

TEST_CASE("status page: a sensor's history as JSON and as a CSV download") {
  const HttpReply json = route_http("GET", "/api/sensors/boom/history", no_sensors, boom_history);
  CHECK(json.status == 200);
  CHECK(json.content_type == "application/json");
  CHECK(json.body == history_json(kBoomHistory));
  CHECK(json.content_disposition.empty());

  const HttpReply csv = route_http("GET", "/api/sensors/boom/history.csv?x=1", no_sensors,
                                   boom_history);
  CHECK(csv.status == 200);
  CHECK(csv.content_type == "text/csv; charset=utf-8");
  CHECK(csv.body == history_csv(kBoomHistory));
  CHECK(csv.body.starts_with("time_utc,unix_ms,x_deg,y_deg\r\n"));
  CHECK(csv.content_disposition == "attachment; filename=\"boom-history.csv\"");

  CHECK(route_http("GET", "/api/sensors/m%61st/history", no_sensors, boom_history).body == "[]");
  CHECK(route_http("HEAD", "/api/sensors/boom/history.csv", no_sensors, boom_history).status ==
        200);
}

TEST_CASE("status page: the history of an unknown sensor is a 404") {
  CHECK(route_http("GET", "/api/sensors/nobody/history", no_sensors, boom_history).status == 404);
  CHECK(route_http("GET", "/api/sensors/nobody/history.csv", no_sensors, boom_history).status ==
        404);
  CHECK(route_http("GET", "/api/sensors/boom/x/history", no_sensors, boom_history).status == 404);
  CHECK(route_http("GET", "/api/sensors/boom/history", no_sensors).status == 404);
  CHECK(route_http("POST", "/api/sensors/boom/history", no_sensors, boom_history).status == 405);
}

TEST_CASE("history recorder: one sample per sensor per snapshot, gaps while stale") {
  HistoryRecorder recorder({"boom", "mast"}, 3);
  GatewayStatus status;
  status.sensors = {sensor("boom", false, 1.5, -0.25), sensor("mast", true, 4.0, 5.0)};
  recorder.record(status, 1000);
  status.sensors[0].x = 1.75;
  recorder.record(status, 2000);

  const auto boom = recorder.history("boom");
  REQUIRE(boom);
  REQUIRE(boom->size() == 2);
  CHECK((*boom)[0].unix_ms == 1000);
  CHECK((*boom)[0].x == 1.5f);
  CHECK((*boom)[0].y == -0.25f);
  CHECK((*boom)[1].x == 1.75f);
  // A stale reading is not drawn as if it were current.
  const auto mast = recorder.history("mast");
  REQUIRE(mast);
  REQUIRE(mast->size() == 2);
  CHECK_FALSE((*mast)[0].x.has_value());
  CHECK_FALSE((*mast)[0].y.has_value());
  CHECK_FALSE(recorder.history("nobody").has_value());
}

TEST_CASE("history recorder: a sensor's ring is bounded and matched by name") {
  HistoryRecorder recorder({"boom", "mast"}, 2);
  GatewayStatus status;
  // Out of configuration order, with a name not configured: each sample still lands in its
  // own sensor's ring.
  status.sensors = {sensor("mast", false, 7.0, 8.0), sensor("ghost", false, 0, 0),
                    sensor("boom", false, 1.0, 2.0)};
  for (std::int64_t t = 1; t <= 5; ++t) recorder.record(status, t);
  const auto boom = recorder.history("boom");
  REQUIRE(boom->size() == 2);
  CHECK((*boom)[0].unix_ms == 4);
  CHECK((*boom)[1].unix_ms == 5);
  CHECK((*boom)[1].x == 1.0f);
  CHECK(recorder.history("mast")->back().x == 7.0f);
}
