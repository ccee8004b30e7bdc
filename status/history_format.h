// A sensor's angle history as the HTTP API serves it: JSON for the status page's graph and CSV
// for a spreadsheet (docs/northbound.md, "HTTP status API and metrics"). Pure.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "status/angle_history.h"

namespace tiltgate {

// [{"t":unix_ms,"x":deg,"y":deg},...], oldest first; a missing angle is null.
std::string history_json(const std::vector<AngleSample>& samples);

// A header line `time_utc,unix_ms,x_deg,y_deg`, then one line per sample, oldest first, with
// the time as ISO 8601 UTC to the millisecond (2026-12-02T01:25:38.250Z); a missing angle is
// an empty field. Lines end in CRLF (RFC 4180).
std::string history_csv(const std::vector<AngleSample>& samples);

// 2026-12-02T01:25:38.250Z for a Unix time in milliseconds.
std::string iso8601_utc(std::int64_t unix_ms);

// The file name a browser saves the CSV as: `<sensor>-history.csv`, with any character other
// than letters, digits, '.', '-' and '_' replaced by '_' so the header stays a plain token.
std::string history_csv_filename(std::string_view sensor);

}  // namespace tiltgate
