// The long record as CSV (monitoring/history_csv.h): the exact text of a small range, the same
// text whether made whole or a batch at a time, and 90 days of 1-minute rows streamed from
// disk in bounded batches.
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "monitoring/history_csv.h"
#include "monitoring/long_record.h"
#include "monitoring/utc_time.h"
#include "unit/monitoring/record_fixtures.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate::monitoring;
using namespace tiltgate::test;

namespace {

constexpr std::int64_t k1201 = 1796644860000;  // 2026-12-07T12:01:00.000Z

std::vector<IntervalRecord> three_rows() {
  IntervalRecord a;  // a single-axis sensor without temperature
  a.start_unix_ms = k1201;
  a.length_ms = 60'000;
  a.samples = 60;
  a.x = {1.25f, 1.2625f, 1.3f};
  a.tilt = {0.5f, 0.75f, 1.0f};
  IntervalRecord b;  // dual axis with temperature, the clock not synchronised
  b.start_unix_ms = k1201 + 60'000;
  b.length_ms = 60'000;
  b.samples = 3;
  b.unsynchronised = 3;
  b.x = {-0.001f, 0.0f, 0.002f};
  b.y = {-3.5f, -2.0f, -1.0f};
  b.tilt = {2.0f, 2.5f, 3.0f};
  b.temperature = {20.5f, 21.0f, 21.5f};
  IntervalRecord c;  // one sample without a reading, after a gap
  c.start_unix_ms = k1201 + 240'000;
  c.length_ms = 60'000;
  c.samples = 1;
  c.unsynchronised = 1;
  return {a, b, c};
}

}  // namespace

TEST_CASE("the CSV of a small range, exactly: a header, one row per interval, empty cells where there is no value") {
  const auto rows = three_rows();
  CHECK(history_csv_header() + history_csv_rows(rows) ==
        "time,samples,x_min,x_mean,x_max,y_min,y_mean,y_max,tilt_min,tilt_mean,tilt_max,"
        "temperature_min,temperature_mean,temperature_max,unsynchronised\r\n"
        "2026-12-07T12:01:00.000Z,60,1.25,1.2625,1.3,,,,0.5,0.75,1,,,,0\r\n"
        "2026-12-07T12:02:00.000Z,3,-0.001,0,0.002,-3.5,-2,-1,2,2.5,3,20.5,21,21.5,3\r\n"
        "2026-12-07T12:05:00.000Z,1,,,,,,,,,,,,,1\r\n");
  CHECK(history_csv_rows({}).empty());
}

TEST_CASE("the CSV made a batch at a time is the CSV made whole") {
  const auto rows = three_rows();
  const std::string whole = history_csv_rows(rows);
  std::string batched;
  for (const auto& row : rows) batched += history_csv_rows(std::span(&row, 1));
  CHECK(batched == whole);
}

TEST_CASE("90 days of 1-minute rows stream from disk as CSV a bounded batch at a time") {
  ScratchDir scratch;
  const auto dir = scratch.path("record/boom");
  constexpr int kRows = 90 * 1440;
  {
    LongRecordOptions options;
    options.sync_every = 0;  // a test's scratch disk: no syncs wanted
    auto record = LongRecord::open(dir, options);
    for (int i = 0; i < kRows; ++i) record.append(interval(i));
    REQUIRE(record.appended() == kRows);
  }
  LongRecordReader reader(dir, kDec7, kDec7 + 90 * kDayMs);
  std::size_t rows = 0;
  std::size_t largest_chunk = 0;
  std::size_t chunks = 0;
  std::string last_line;
  for (auto batch = reader.next(); !batch.empty(); batch = reader.next()) {
    CHECK(batch.size() <= LongRecordReader::kDefaultBatch);
    const std::string text = history_csv_rows(batch);
    largest_chunk = std::max(largest_chunk, text.size());
    rows += batch.size();
    ++chunks;
    last_line = text.substr(text.rfind('\n', text.size() - 2) + 1);
  }
  CHECK(rows == kRows);
  CHECK(chunks == 90);
  CHECK(largest_chunk < 1440 * 120);  // a day's rows at a time, never the range's
  CHECK(last_line.rfind("2027-03-06T23:59:00.000Z,60,", 0) == 0);
  CHECK(reader.corrupt() == 0);
  CHECK(reader.problems().empty());
}
