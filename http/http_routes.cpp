#include "http/http_routes.h"

#include <algorithm>
#include <chrono>

#include "status/history_format.h"
#include "status/status_json.h"
#include "status/status_metrics.h"
#include "status/status_page_css.h"
#include "status/status_page_html.h"
#include "status/config_forms_js.h"
#include "status/traffic_view_js.h"
#include "status/status_page_js.h"

namespace tiltgate {

namespace {

constexpr std::string_view kJson = "application/json";
constexpr std::string_view kSensorPrefix = "/api/sensors/";
constexpr std::string_view kHistoryJsonSuffix = "/history";
constexpr std::string_view kHistoryCsvSuffix = "/history.csv";

HttpReply text(unsigned status, std::string body) {
  return HttpReply{status, "text/plain; charset=utf-8", std::move(body)};
}

HttpReply json(std::string body) { return HttpReply{200, std::string(kJson), std::move(body)}; }

// The wall clock as Unix seconds: /api/status's uptime counts from the Unix start time.
double unix_seconds_now() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// GET /api/sensors/NAME/history and .../history.csv; `encoded_name` is still %-escaped.
HttpReply history_reply(std::string_view encoded_name, bool csv, const HistorySource& history) {
  const auto name = path_name(encoded_name);
  if (!name) return text(404, "no such sensor\n");
  std::optional<std::vector<AngleSample>> samples =
      history ? history(*name) : std::optional<std::vector<AngleSample>>{};
  if (!samples) return text(404, "no such sensor\n");
  if (!csv) return json(history_json(*samples));
  HttpReply reply{200, "text/csv; charset=utf-8", history_csv(*samples)};
  reply.content_disposition =
      "attachment; filename=\"" + history_csv_filename(*name) + "\"";
  return reply;
}

}  // namespace

std::optional<std::string> percent_decoded(std::string_view path) {
  std::string out;
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (path[i] != '%') {
      out += path[i];
      continue;
    }
    if (i + 2 >= path.size()) return std::nullopt;
    auto hex = [](char c) -> int {
      if (c >= '0' && c <= '9') return c - '0';
      if (c >= 'a' && c <= 'f') return c - 'a' + 10;
      if (c >= 'A' && c <= 'F') return c - 'A' + 10;
      return -1;
    };
    const int high = hex(path[i + 1]);
    const int low = hex(path[i + 2]);
    if (high < 0 || low < 0) return std::nullopt;
    out += char(high * 16 + low);
    i += 2;
  }
  return out;
}

std::string query_value(std::string_view target, std::string_view name) {
  const auto mark = target.find('?');
  if (mark == std::string_view::npos) return {};
  std::string_view query = target.substr(mark + 1);
  while (!query.empty()) {
    const auto end = query.find('&');
    const std::string_view pair = query.substr(0, end);
    const auto equals = pair.find('=');
    if (equals != std::string_view::npos && pair.substr(0, equals) == name) {
      std::string raw(pair.substr(equals + 1));
      std::replace(raw.begin(), raw.end(), '+', ' ');
      return percent_decoded(raw).value_or(std::string());
    }
    if (end == std::string_view::npos) break;
    query = query.substr(end + 1);
  }
  return {};
}

std::optional<std::string> path_name(std::string_view text) {
  auto name = percent_decoded(text);
  if (!name || name->find('/') != std::string::npos) return std::nullopt;
  return name;
}

HttpReply route_http(std::string_view method, std::string_view target,
                     const StatusSource& status, const HistorySource& history) {
  if (method != "GET" && method != "HEAD") {
    HttpReply reply = text(405, "only GET: the status API is read-only\n");
    reply.allow_get = true;
    return reply;
  }
  const std::string_view path = target.substr(0, target.find('?'));
  if (path == "/" || path == "/index.html")
    return HttpReply{200, "text/html; charset=utf-8", std::string(kStatusPage)};
  // The page's style sheet and script, files of their own: the Content-Security-Policy
  // (http/http_server.cpp) allows no inline style or script.
  if (path == "/status_page.css")
    return HttpReply{200, "text/css; charset=utf-8", std::string(kStatusPageCss)};
  if (path == "/status_page.js")
    return HttpReply{200, "text/javascript; charset=utf-8", std::string(kStatusPageJs)};
  if (path == "/config_forms.js")  // the console's guided configuration
    return HttpReply{200, "text/javascript; charset=utf-8", std::string(kConfigFormsJs)};
  if (path == "/traffic_view.js")  // the console's traffic view
    return HttpReply{200, "text/javascript; charset=utf-8", std::string(kTrafficViewJs)};
  if (path == "/healthz") return text(200, "ok\n");
  if (path == "/metrics")
    return HttpReply{200, std::string(kMetricsContentType), metrics_text(status())};
  if (path == "/api/sensors") return json(sensors_json(status().sensors));
  if (path == "/api/buses") return json(buses_json(status().buses));
  if (path == "/api/modbus") return json(modbus_json(status()));
  if (path == "/api/status") return json(gateway_state_json(status(), unix_seconds_now()));
  if (path.starts_with(kSensorPrefix)) {
    const std::string_view rest = path.substr(kSensorPrefix.size());
    if (rest.ends_with(kHistoryCsvSuffix))
      return history_reply(rest.substr(0, rest.size() - kHistoryCsvSuffix.size()), true, history);
    if (rest.ends_with(kHistoryJsonSuffix))
      return history_reply(rest.substr(0, rest.size() - kHistoryJsonSuffix.size()), false,
                           history);
    const auto name = percent_decoded(path.substr(kSensorPrefix.size()));
    if (name) {
      for (const SensorStatus& sensor : status().sensors)
        if (sensor.name == *name) return json(sensor_json(sensor));
    }
    return text(404, "no such sensor\n");
  }
  return text(404, "not found: the endpoints are / (with /status_page.css, /status_page.js, "
                   "/config_forms.js and /traffic_view.js), "
                   "/healthz, /api/sensors, /api/sensors/NAME, /api/sensors/NAME/history[.csv], "
                   "/api/buses, /api/modbus, /api/status and /metrics\n");
}

}  // namespace tiltgate
