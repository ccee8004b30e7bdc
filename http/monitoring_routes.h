// The monitoring's endpoints (docs/monitoring.md): answered on the HTTP server's thread, not the
// gateway's, since a long record's download reads files. Read-only like the rest of the API.
//
//   GET /api/events?sensor=&kind=&from=&to=&limit=    the events kept, newest first
//   GET /api/sensors/NAME/history.csv?from=&to=       the sensor's long record as CSV
//   GET /api/sensors/NAME/bursts                      its burst records, newest first
//   GET /api/sensors/NAME/bursts/ID.csv               one of them
//
// `from` and `to` are Unix milliseconds or UTC ISO 8601 (monitoring/history_csv.h); `limit` is
// 1..10000, 100 by default.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"
#include "http/http_routes.h"
#include "monitoring/event_log.h"

namespace tiltgate {

struct MonitoringSource {
  std::function<std::vector<monitoring::EventRecord>(const monitoring::EventQuery&)> events;
  // The CSV of the sensor's long record for [from, to), merged into at most `points` rows
  // unless 0 (monitoring/record_download.h); none for a sensor not configured, an error for a
  // range too long to answer at once.
  std::function<std::optional<Expected<std::string, std::string>>(
      const std::string& sensor, std::int64_t from_unix_ms, std::int64_t to_unix_ms,
      std::size_t points)>
      long_record_csv;
  // The directory of the sensor's burst records (monitoring/burst_files.h); none for a sensor
  // not configured, an empty path when none are kept.
  std::function<std::optional<std::filesystem::path>(const std::string& sensor)> bursts;
};

// The reply when `target` is one of the monitoring's endpoints (GET or HEAD); none otherwise,
// for the other routes to answer. A history.csv without from or to is not the monitoring's:
// it is the recent history's (http/http_routes.h).
std::optional<HttpReply> route_monitoring(std::string_view method, std::string_view target,
                                          const MonitoringSource& source,
                                          std::int64_t now_unix_ms);

}  // namespace tiltgate
