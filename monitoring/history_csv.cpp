#include "monitoring/history_csv.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>

#include "monitoring/utc_time.h"

namespace tiltgate::monitoring {

namespace {

void append_value(std::string& out, float value) {
  out += ',';
  // fmt's shortest round-trip form of the float: 1.25, not 1.25000000000.
  if (!std::isnan(value)) fmt::format_to(std::back_inserter(out), "{}", value);
}

void append_channel(std::string& out, const ChannelStats& channel) {
  append_value(out, channel.min);
  append_value(out, channel.mean);
  append_value(out, channel.max);
}

}  // namespace

std::string history_csv_header() {
  return "time,samples,x_min,x_mean,x_max,y_min,y_mean,y_max,tilt_min,tilt_mean,tilt_max,"
         "temperature_min,temperature_mean,temperature_max,unsynchronised\r\n";
}

std::string history_csv_rows(std::span<const IntervalRecord> rows) {
  std::string out;
  out.reserve(rows.size() * 120);
  for (const IntervalRecord& row : rows) {
    out += utc_timestamp(row.start_unix_ms);
    fmt::format_to(std::back_inserter(out), ",{}", row.samples);
    append_channel(out, row.x);
    append_channel(out, row.y);
    append_channel(out, row.tilt);
    append_channel(out, row.temperature);
    fmt::format_to(std::back_inserter(out), ",{}\r\n", row.unsynchronised);
  }
  return out;
}

}  // namespace tiltgate::monitoring
