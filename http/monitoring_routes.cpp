#include "http/monitoring_routes.h"

#include <charconv>

#include "monitoring/burst_files.h"
#include "monitoring/history_csv.h"
#include "monitoring/record_download.h"
#include "status/history_format.h"
#include "status/json_values.h"
#include "store/file_io.h"

namespace tiltgate {

namespace {

constexpr std::string_view kEventsPath = "/api/events";
constexpr std::string_view kSensorsPath = "/api/sensors/";
constexpr std::string_view kLongCsvSuffix = "/history.csv";
constexpr std::string_view kBursts = "/bursts";
constexpr std::size_t kMaxEventLimit = monitoring::kEventsInMemory;

HttpReply plain(unsigned status, std::string body) {
  return HttpReply{status, "text/plain; charset=utf-8", std::move(body)};
}

// `name`'s value as a time, when given; the error names the parameter.
Expected<std::optional<std::int64_t>, std::string> time_parameter(std::string_view target,
                                                                  std::string_view name) {
  const std::string value = query_value(target, name);
  if (value.empty()) return std::optional<std::int64_t>{};
  auto parsed = monitoring::parse_time_query(value);
  if (!parsed) return Unexpected(std::string(name) + ": " + parsed.error());
  return std::optional<std::int64_t>(*parsed);
}

Json event_object(const monitoring::EventRecord& event) {
  return Json::parse(monitoring::event_json(event));
}

// `name`'s value as a whole number 1..max, 0 when not given; the error says what is wanted.
Expected<std::size_t, std::string> count_parameter(std::string_view target, std::string_view name,
                                                   std::size_t max) {
  const std::string value = query_value(target, name);
  if (value.empty()) return std::size_t{0};
  std::size_t n = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), n);
  if (error != std::errc{} || end != value.data() + value.size() || n < 1 || n > max)
    return Unexpected(std::string(name) + ": expected a whole number 1.." + std::to_string(max) +
                      ", got \"" + value.substr(0, 40) + "\"");
  return n;
}

HttpReply events_reply(std::string_view target, const MonitoringSource& source) {
  monitoring::EventQuery query;
  query.sensor = query_value(target, "sensor");
  query.kind = query_value(target, "kind");
  auto from = time_parameter(target, "from");
  if (!from) return plain(400, from.error() + "\n");
  auto to = time_parameter(target, "to");
  if (!to) return plain(400, to.error() + "\n");
  query.since = *from;
  query.until = *to;
  auto limit = count_parameter(target, "limit", kMaxEventLimit);
  if (!limit) return plain(400, limit.error() + "\n");
  if (*limit > 0) query.limit = *limit;
  Json array = Json::array();
  if (source.events)
    for (const monitoring::EventRecord& event : source.events(query))
      array.push_back(event_object(event));
  return HttpReply{200, "application/json", json_text(array)};
}

HttpReply long_record_reply(std::string_view encoded_name, std::string_view target,
                            const MonitoringSource& source, std::int64_t now_unix_ms) {
  const auto name = path_name(encoded_name);
  if (!name) return plain(404, "no such sensor\n");
  auto from = time_parameter(target, "from");
  if (!from) return plain(400, from.error() + "\n");
  auto to = time_parameter(target, "to");
  if (!to) return plain(400, to.error() + "\n");
  // One side alone: the other is the record's start, or now.
  const std::int64_t start = from->value_or(0);
  const std::int64_t end = to->value_or(now_unix_ms + 1);
  if (end <= start) return plain(400, "to must be after from\n");
  auto points = count_parameter(target, "points", monitoring::kMaxGraphPoints);
  if (!points) return plain(400, points.error() + "\n");
  if (!source.long_record_csv) return plain(404, "no long record is kept\n");
  auto csv = source.long_record_csv(*name, start, end, *points);
  if (!csv) return plain(404, "no such sensor\n");
  if (!*csv) return plain(413, csv->error() + "\n");
  HttpReply reply{200, "text/csv; charset=utf-8", std::move(**csv)};
  reply.content_disposition = "attachment; filename=\"" + history_csv_filename(*name) + "\"";
  return reply;
}

// GET /api/sensors/NAME/bursts[/ID.csv]; `rest` is what follows the sensor's name.
HttpReply bursts_reply(std::string_view encoded_name, std::string_view rest,
                       const MonitoringSource& source) {
  const auto name = path_name(encoded_name);
  const std::optional<std::filesystem::path> dir =
      name && source.bursts ? source.bursts(*name) : std::nullopt;
  if (!dir) return plain(404, "no such sensor\n");
  if (rest == kBursts) {
    Json list = Json::array();
    if (!dir->empty())
      for (const monitoring::BurstFile& burst : monitoring::list_bursts(*dir))
        list.push_back({{"id", burst.id}, {"time", iso8601_utc(burst.unix_ms)},
                        {"unix_ms", burst.unix_ms}, {"bytes", burst.bytes}});
    return HttpReply{200, "application/json", json_text(list)};
  }
  std::string_view id = rest.substr(kBursts.size() + 1);  // after "/bursts/"
  if (!id.ends_with(".csv")) return plain(404, "not found: ask for ID.csv\n");
  id.remove_suffix(4);
  const auto path = dir->empty() ? std::nullopt : monitoring::burst_path(*dir, id);
  if (!path) return plain(404, "no such burst\n");
  auto bytes = store::read_whole(*path);
  if (!bytes) return plain(404, "no such burst\n");
  HttpReply reply{200, "text/csv; charset=utf-8", std::string(bytes->begin(), bytes->end())};
  reply.content_disposition =
      "attachment; filename=\"" + history_csv_filename(*name + "-burst-" + std::string(id)) + "\"";
  return reply;
}

}  // namespace

std::optional<HttpReply> route_monitoring(std::string_view method, std::string_view target,
                                          const MonitoringSource& source,
                                          std::int64_t now_unix_ms) {
  if (method != "GET" && method != "HEAD") return std::nullopt;
  const std::string_view path = target.substr(0, target.find('?'));
  if (path == kEventsPath) return events_reply(target, source);
  if (path.starts_with(kSensorsPath)) {
    const std::string_view after = path.substr(kSensorsPath.size());
    const auto slash = after.find('/');
    if (slash != std::string_view::npos && after.substr(slash).starts_with(kBursts) &&
        (after.substr(slash) == kBursts || after.substr(slash).starts_with("/bursts/")))
      return bursts_reply(after.substr(0, slash), after.substr(slash), source);
  }
  if (path.starts_with(kSensorsPath) && path.ends_with(kLongCsvSuffix)) {
    if (query_value(target, "from").empty() && query_value(target, "to").empty())
      return std::nullopt;  // the recent history's CSV
    const std::string_view name =
        path.substr(kSensorsPath.size(), path.size() - kSensorsPath.size() - kLongCsvSuffix.size());
    return long_record_reply(name, target, source, now_unix_ms);
  }
  return std::nullopt;
}

}  // namespace tiltgate
