#include "monitoring/record_download.h"

#include <fmt/format.h>

#include <optional>
#include <vector>

#include "monitoring/history_csv.h"
#include "monitoring/interval_merge.h"
#include "monitoring/long_record_reader.h"

namespace tiltgate::monitoring {

namespace {

// The range's rows merged into at most about `points` (the first row's interval tells the
// record's own).
std::string merged_csv(LongRecordReader& reader, std::int64_t range_ms, std::size_t points) {
  std::string out = history_csv_header();
  std::optional<IntervalMerge> merge;
  std::vector<IntervalRecord> merged;
  for (auto batch = reader.next(); !batch.empty(); batch = reader.next()) {
    for (const IntervalRecord& row : batch) {
      if (!merge)
        merge.emplace(graph_step_ms(range_ms, static_cast<std::int64_t>(points), row.length_ms));
      if (auto point = merge->add(row)) merged.push_back(*point);
    }
    out += history_csv_rows(merged);
    merged.clear();
  }
  if (merge)
    if (auto point = merge->finish()) merged.push_back(*point);
  return out + history_csv_rows(merged);
}

}  // namespace

Expected<std::string, std::string> record_csv(const std::filesystem::path& dir,
                                              std::int64_t from_unix_ms, std::int64_t to_unix_ms,
                                              std::size_t max_rows, std::size_t points) {
  std::string out = history_csv_header();
  if (dir.empty()) return out;
  LongRecordReader reader(dir, from_unix_ms, to_unix_ms);
  if (points > 0) return merged_csv(reader, to_unix_ms - from_unix_ms, points);
  std::size_t rows = 0;
  for (auto batch = reader.next(); !batch.empty(); batch = reader.next()) {
    rows += batch.size();
    if (rows > max_rows)
      return Unexpected(fmt::format("more than {} rows in that range: ask for a shorter one "
                                    "(from= and to=)", max_rows));
    out += history_csv_rows(batch);
  }
  return out;
}

}  // namespace tiltgate::monitoring
