// A sensor's long record as CSV (docs/monitoring.md, "The long record"): what the console's
// `/api/sensors/NAME/history.csv?from=&to=` and the command line give for a time range, and the
// `from`/`to` values they take. Pure.
//
// Made a batch at a time, so a range of any length streams: the header once, then the rows of
// each batch a LongRecordReader gives (monitoring/long_record_reader.h shows the loop). Lines
// end in CRLF (RFC 4180), as the status page's recent history CSV does:
//
//   time,samples,x_min,x_mean,x_max,y_min,y_mean,y_max,tilt_min,tilt_mean,tilt_max,temperature_min,temperature_mean,temperature_max,unsynchronised
//   2026-12-07T12:01:00.000Z,60,1.25,1.2625,1.3,,,,1.25,1.2625,1.3,,,,0
//
// `time` is the interval's start in UTC, `samples` how many samples it summed up,
// `unsynchronised` how many of them were taken while the clock was not synchronised; a value
// is the shortest text that reads back as the stored float, and empty where there is none.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "driver/expected.h"
#include "monitoring/interval_record.h"

namespace tiltgate::monitoring {

// The header line, CRLF included.
std::string history_csv_header();
// One line per interval, in the order given, each ending in CRLF.
std::string history_csv_rows(std::span<const IntervalRecord> rows);

// A `from` or `to` value as Unix milliseconds: Unix milliseconds themselves (1796637600000) or
// a UTC time in ISO 8601, `2026-12-07T10:00Z`, `2026-12-07T10:00:00Z`, with a fraction of a
// second (`.250Z`, up to 9 digits, cut to the millisecond), or a date alone (`2026-12-07`,
// its midnight). Anything else is an error that says what is taken (the value quoted, at most
// 40 characters of it, anything not printable ASCII shown as '?').
Expected<std::int64_t, std::string> parse_time_query(std::string_view text);

}  // namespace tiltgate::monitoring
