// A range of the long record as one CSV answer (monitoring/record_download.h): every row up to
// the bound, a longer range refused with what to do, and for a graph the rows merged into at
// most the points asked, each with the least and greatest of what it covers.
#include <doctest/doctest.h>

#include <sstream>
#include <string>
#include <vector>

#include "monitoring/long_record.h"
#include "monitoring/record_download.h"
#include "unit/monitoring/record_fixtures.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate::monitoring;
using namespace tiltgate::test;

namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The cells of one CSV line.
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line.substr(0, line.find('\r')));
  for (std::string cell; std::getline(in, cell, ',');) out.push_back(cell);
  return out;
}

}  // namespace

TEST_CASE("the long record's CSV: every row of the range, and a range past the bound refused") {
  ScratchDir scratch;
  const std::string dir = scratch.path("record/boom");
  auto record = LongRecord::open(dir);
  append(record, 0, 120);  // two hours of minutes
  const auto csv = record_csv(dir, kDec7, kDec7 + 60 * kMinute);
  REQUIRE(csv.has_value());
  CHECK(lines_of(*csv).size() == 1 + 60);
  const auto refused = record_csv(dir, kDec7, kDec7 + 120 * kMinute, 100);
  REQUIRE_FALSE(refused.has_value());
  CHECK(refused.error().find("more than 100 rows") != std::string::npos);
}

TEST_CASE("the long record's CSV for a graph: two hours of minutes merged into 5-minute steps") {
  ScratchDir scratch;
  const std::string dir = scratch.path("record/boom");
  auto record = LongRecord::open(dir);
  append(record, 0, 120);
  // 24 points over 2 h: 5 minutes a step (graph_step_ms), merged whatever the row bound.
  const auto csv = record_csv(dir, kDec7, kDec7 + 120 * kMinute, 10, 24);
  REQUIRE(csv.has_value());
  const std::vector<std::string> lines = lines_of(*csv);
  REQUIRE(lines.size() == 1 + 24);
  const std::vector<std::string> head = cells(lines[0]);
  CHECK(head[0] == "time");
  CHECK(head[1] == "samples");
  CHECK(head[2] == "x_min");
  // The first step holds minutes 0..4: x from -0.5 to 4.5, its mean 2, 5 x 60 samples.
  const std::vector<std::string> first = cells(lines[1]);
  CHECK(first[0] == "2026-12-07T00:00:00.000Z");
  CHECK(first[1] == "300");
  CHECK(std::stod(first[2]) == doctest::Approx(-0.5));
  CHECK(std::stod(first[3]) == doctest::Approx(2.0));
  CHECK(std::stod(first[4]) == doctest::Approx(4.5));
  CHECK(cells(lines[24])[0] == "2026-12-07T01:55:00.000Z");
  // Asked for more points than there are rows: the rows as they are.
  const auto fine = record_csv(dir, kDec7, kDec7 + 120 * kMinute, kMaxDownloadRows, 1000);
  REQUIRE(fine.has_value());
  CHECK(lines_of(*fine).size() == 1 + 120);
  // An empty range: the header alone.
  const auto none = record_csv(dir, kDec7 + 500 * kMinute, kDec7 + 600 * kMinute, 10, 24);
  REQUIRE(none.has_value());
  CHECK(lines_of(*none).size() == 1);
}
