// The long record zoomed out (docs/monitoring.md, "The long record"): a range's intervals merged
// into coarser ones, so the console's graph draws weeks of 1-minute rows as a few hundred
// points, each with the least and greatest of what it covers (a spike of one minute still
// shows in a week's view). Pure; fed in time order, as LongRecordReader gives them.
//
//   LongRecordReader reader(dir, from, to);
//   IntervalMerge merge(graph_step_ms(to - from, 500, 60'000));
//   for (auto rows = reader.next(); !rows.empty(); rows = reader.next())
//     for (const auto& row : rows)
//       if (auto point = merge.add(row)) draw(*point);
//   if (auto point = merge.finish()) draw(*point);
#pragma once

#include <cstdint>
#include <optional>

#include "monitoring/interval_record.h"

namespace tiltgate::monitoring {

class IntervalMerge {
 public:
  // Merged intervals of `step_ms` (at least 1), aligned to UTC multiples of it.
  explicit IntervalMerge(std::int64_t step_ms);

  // Adds one interval of the record; returns the merged one it closed, when it starts a later
  // step. An interval is in the step its start is in; one before the current step (out of
  // order) is ignored.
  std::optional<IntervalRecord> add(const IntervalRecord& interval);
  // The step being merged, closed: at the end of the range.
  std::optional<IntervalRecord> finish();

 private:
  std::int64_t step_ms_ = 1;
  std::optional<IntervalRecord> open_;
};

// The step a graph of a range `range_ms` long shows at most `max_points` points at: the record's
// own interval when it fits, else the least of 1, 5, 15 and 30 minutes, 1, 3, 6 and 12 hours and
// whole days that does.
std::int64_t graph_step_ms(std::int64_t range_ms, std::int64_t max_points,
                           std::int64_t record_interval_ms);

}  // namespace tiltgate::monitoring
