// The long record zoomed out for the console's graph (monitoring/interval_merge.h): intervals
// merged into coarser steps keep the least and greatest of what they cover, and the step chosen
// keeps a range's points within what a graph draws.
#include <doctest/doctest.h>

#include <cmath>
#include <vector>

#include "monitoring/interval_merge.h"
#include "unit/monitoring/record_fixtures.h"

using namespace tiltgate::monitoring;
using namespace tiltgate::test;

namespace {

std::vector<IntervalRecord> merged(const std::vector<IntervalRecord>& rows, std::int64_t step) {
  IntervalMerge merge(step);
  std::vector<IntervalRecord> out;
  for (const auto& row : rows)
    if (auto point = merge.add(row)) out.push_back(*point);
  if (auto point = merge.finish()) out.push_back(*point);
  return out;
}

}  // namespace

TEST_CASE("minutes merged into 5-minute steps: least of the least, greatest of the greatest, means weighted by samples") {
  std::vector<IntervalRecord> rows;
  for (int i = 0; i < 10; ++i) rows.push_back(interval(i));  // x of minute i: i-0.5, i, i+0.5
  rows[7].samples = 180;                                      // three times the weight
  rows[7].temperature = {20.0f, 21.0f, 22.0f};                // temperature in one minute only
  const auto steps = merged(rows, 5 * kMinute);
  REQUIRE(steps.size() == 2);
  CHECK(steps[0].start_unix_ms == kDec7);
  CHECK(steps[0].length_ms == 5 * kMinute);
  CHECK(steps[0].samples == 300);
  CHECK(steps[0].unsynchronised == 2);  // minutes 1 and 3
  CHECK(steps[0].x.min == -0.5f);
  CHECK(steps[0].x.mean == 2.0f);
  CHECK(steps[0].x.max == 4.5f);
  CHECK(std::isnan(steps[0].y.mean));
  CHECK(steps[1].start_unix_ms == kDec7 + 5 * kMinute);
  CHECK(steps[1].samples == 420);
  CHECK(steps[1].x.mean == doctest::Approx((5 + 6 + 3 * 7 + 8 + 9) * 60.0 / 420));
  CHECK(steps[1].temperature.mean == 21.0f);
  CHECK(steps[1].temperature.max == 22.0f);
}

TEST_CASE("a gap leaves no empty step, and an interval out of order is left out") {
  const auto steps = merged({interval(0), interval(61), interval(62), interval(3)}, 60 * kMinute);
  REQUIRE(steps.size() == 2);
  CHECK(steps[0].start_unix_ms == kDec7);
  CHECK(steps[0].samples == 60);
  CHECK(steps[1].start_unix_ms == kDec7 + 60 * kMinute);
  CHECK(steps[1].samples == 120);
  CHECK(merged({}, kMinute).empty());
}

TEST_CASE("a graph's step: the record's own interval while it fits, then the least round step that does") {
  const std::int64_t hour = 60 * kMinute;
  CHECK(graph_step_ms(2 * hour, 500, kMinute) == kMinute);         // 120 points
  CHECK(graph_step_ms(24 * hour, 500, kMinute) == 5 * kMinute);    // 288 points
  CHECK(graph_step_ms(7 * 24 * hour, 500, kMinute) == 30 * kMinute);  // 336 points
  CHECK(graph_step_ms(91 * 24 * hour, 500, kMinute) == 6 * hour);  // 364 points
  CHECK(graph_step_ms(3 * 365 * 24 * hour, 500, kMinute) == 3 * 24 * hour);
  CHECK(graph_step_ms(10 * kMinute, 500, 10'000) == 10'000);       // a 10 s record, zoomed in
  CHECK(graph_step_ms(24 * hour, 500, 10 * kMinute) == 10 * kMinute);
}
