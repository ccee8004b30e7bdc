// The long record's bytes (monitoring/record_format.h): a record's 72 bytes and their CRC, the
// file header, and the day files' names.
#include <doctest/doctest.h>

#include <cmath>

#include "monitoring/record_format.h"
#include "monitoring/utc_time.h"
#include "unit/monitoring/record_fixtures.h"

using namespace tiltgate::monitoring;
using namespace tiltgate::test;

TEST_CASE("a record is 72 bytes, little-endian, and reads back the same, no value kept as none") {
  const IntervalRecord r = interval(61);
  const RecordBytes bytes = encode_record(r);
  // The start, 2026-12-07T01:01:00Z, little-endian at 0.
  std::uint64_t start = 0;
  for (int i = 0; i < 8; ++i) start |= static_cast<std::uint64_t>(bytes[i]) << (8 * i);
  CHECK(start == static_cast<std::uint64_t>(kDec7 + 61 * kMinute));
  CHECK(bytes[8] == 0x60);  // 60000 ms = 0xEA60
  CHECK(bytes[9] == 0xEA);
  const auto back = decode_record(bytes);
  REQUIRE(back.has_value());
  CHECK(equal(*back, r));
  CHECK(std::isnan(back->y.mean));
  CHECK(std::isnan(back->temperature.max));
}

TEST_CASE("a record with any bit flipped, or of zeros, is not a record") {
  const RecordBytes good = encode_record(interval(3));
  for (std::size_t byte : {0u, 9u, 20u, 67u, 70u}) {
    RecordBytes bad = good;
    bad[byte] ^= 0x10;
    CHECK_FALSE(decode_record(bad).has_value());
  }
  CHECK_FALSE(decode_record(RecordBytes{}).has_value());  // a power cut's zeros
}

TEST_CASE("a day file starts with a 16-byte header naming the format and the record size") {
  const FileHeader header = file_header();
  CHECK(std::string(header.begin(), header.begin() + 8) == "tgrecord");
  CHECK(header[8] == 1);
  CHECK(header[10] == 72);
  CHECK(is_file_header(header));
  FileHeader other = header;
  other[10] = 80;  // another record size: another format
  CHECK_FALSE(is_file_header(other));
  CHECK(whole_records(16 + 72 * 3) == 3);
  CHECK(whole_records(16 + 72 * 3 + 71) == 3);  // a record cut short is not one
  CHECK(records_end(3) == 16 + 72 * 3);
}

TEST_CASE("a day file is named by its UTC date, and only such names are the record's") {
  const std::int64_t day = utc_day(kDec7 + 12 * 3'600'000);
  CHECK(record_file_name(day) == "2026-12-07.rec");
  CHECK(record_file_name(utc_day(kDec7 - 1)) == "2026-12-06.rec");
  CHECK(record_file_name(utc_day(-1)) == "1969-12-31.rec");
  const auto parsed = parse_record_file_name("2026-12-07.rec");
  REQUIRE(parsed.has_value());
  CHECK(parsed->day == day);
  CHECK_FALSE(parsed->damaged);
  const auto damaged = parse_record_file_name("2026-12-07.rec.damaged");
  REQUIRE(damaged.has_value());
  CHECK(damaged->damaged);
  CHECK(damaged->day == day);
  for (const char* other : {"2026-12-07.rec.tmp", "2026-12-7.rec", "2026-13-01.rec",
                            "2026-02-30.rec", "lock", "2026-12-07", "x2026-12-07.rec"})
    CHECK_FALSE(parse_record_file_name(other).has_value());
}

TEST_CASE("UTC days and timestamps") {
  CHECK(utc_day(0) == 0);
  CHECK(utc_day(-1) == -1);
  CHECK(utc_day(kDec7) == utc_day(kDec7 + 86'399'999));
  CHECK(utc_date_text(utc_day(kDec7)) == "2026-12-07");
  CHECK(parse_utc_date("2026-12-07") == utc_day(kDec7));
  CHECK(parse_utc_date("2024-02-29").has_value());
  CHECK_FALSE(parse_utc_date("2026-02-29").has_value());
  CHECK(utc_timestamp(0) == "1970-01-01T00:00:00.000Z");
  CHECK(utc_timestamp(kDec7 + 43'261'005) == "2026-12-07T12:01:01.005Z");
  CHECK(utc_timestamp(-1) == "1969-12-31T23:59:59.999Z");
}
