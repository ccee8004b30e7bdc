// A range of a sensor's long record as one CSV text (monitoring/history_csv.h): what
// `GET /api/sensors/NAME/history.csv?from=&to=` answers and `tiltgate history` writes. Read
// from the files (monitoring/long_record_reader.h), so it runs beside the gateway appending,
// on an HTTP thread or in another process. Bounded: at most kMaxDownloadRows rows in one
// answer (91 days of 1-minute rows, some 15 MB); a longer range is an error saying so. For a
// graph, `points` merges the rows into at most that many (monitoring/interval_merge.h), so
// any range kept answers in a few hundred rows.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>

#include "driver/expected.h"

namespace tiltgate::monitoring {

inline constexpr std::size_t kMaxDownloadRows = 131'072;
// The most points a merged answer may be asked for (`points`).
inline constexpr std::size_t kMaxGraphPoints = 10'000;

// `points` 0: every row, at most `max_rows`; else the rows merged into steps of
// graph_step_ms(to - from, points, the record's interval), whatever the range's length.
Expected<std::string, std::string> record_csv(const std::filesystem::path& dir,
                                              std::int64_t from_unix_ms, std::int64_t to_unix_ms,
                                              std::size_t max_rows = kMaxDownloadRows,
                                              std::size_t points = 0);

}  // namespace tiltgate::monitoring
