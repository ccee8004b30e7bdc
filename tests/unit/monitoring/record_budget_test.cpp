// The disk the long record takes (monitoring/record_budget.h), as `tiltgate check` shows it.
#include <doctest/doctest.h>

#include "monitoring/record_budget.h"
#include "monitoring/record_format.h"

using namespace tiltgate::monitoring;

TEST_CASE("a day's file: a header and a record per interval of the day, in whole 4 KiB blocks") {
  CHECK(record_day_file_bytes(60) == 106'496);      // 16 + 72 x 1440 = 103,696: 26 blocks
  CHECK(record_day_file_bytes(300) == 24'576);      // 16 + 72 x 288 = 20,752: 6 blocks
  CHECK(record_day_file_bytes(7) == 888'832);       // ceil(86400 / 7) = 12,343 intervals
  CHECK(record_day_file_bytes(1) == 6'221'824);     // 86,400 intervals
  CHECK(record_day_file_bytes(0) == record_day_file_bytes(1));
  CHECK(record_day_file_bytes(86'400) == 4'096);    // one interval: one block
}

TEST_CASE("a sensor keeps keep_days files and the day being written, and the total is per sensor times sensors") {
  CHECK(record_bytes_per_sensor(91, 60) == 92 * 106'496);
  CHECK(record_bytes_per_sensor(0, 60) == 106'496);
  CHECK(record_bytes_total(12, 91, 60) == 117'571'584);
  CHECK(record_bytes_total(0, 91, 60) == 0);
}

TEST_CASE("the budget as tiltgate check prints it") {
  CHECK(record_budget_text(12, 91, 60) == "long record: 12 sensors x 91 days at 60 s: 117.6 MB");
  CHECK(record_budget_text(1, 1, 60) == "long record: 1 sensor x 1 day at 60 s: 213.0 kB");
  CHECK(record_budget_text(60, 365, 1) == "long record: 60 sensors x 365 days at 1 s: 136.6 GB");
  CHECK(disk_bytes_text(512) == "512 bytes");
  CHECK(disk_bytes_text(1'500'000'000) == "1.5 GB");
}
