// The `from` and `to` values of a long record download (monitoring/history_csv.h,
// parse_time_query): Unix milliseconds or ISO 8601 UTC, and an error that says why for
// anything else.
#include <doctest/doctest.h>

#include <string>

#include "monitoring/history_csv.h"

using namespace tiltgate::monitoring;

namespace {

constexpr std::int64_t k10 = 1796637600000;  // 2026-12-07T10:00:00.000Z

std::string error_of(std::string_view text) {
  const auto parsed = parse_time_query(text);
  REQUIRE_FALSE(parsed.has_value());
  return parsed.error();
}

}  // namespace

TEST_CASE("a time is Unix milliseconds or ISO 8601 UTC, with or without seconds and milliseconds, or a date") {
  CHECK(parse_time_query("1796637600000").value() == k10);
  CHECK(parse_time_query("0").value() == 0);
  CHECK(parse_time_query("2026-12-07T10:00:00Z").value() == k10);
  CHECK(parse_time_query("2026-12-07T10:00Z").value() == k10);
  CHECK(parse_time_query("2026-12-07T10:00:00.250Z").value() == k10 + 250);
  CHECK(parse_time_query("2026-12-07T10:00:00.5Z").value() == k10 + 500);
  CHECK(parse_time_query("2026-12-07T10:00:00.123456789Z").value() == k10 + 123);
  CHECK(parse_time_query("2026-12-07T23:59:59.999Z").value() == k10 + 14 * 3'600'000 - 1);
  CHECK(parse_time_query("2026-12-07").value() == k10 - 10 * 3'600'000);
  CHECK(parse_time_query("2024-02-29T00:00Z").has_value());
}

TEST_CASE("anything else is refused, saying what is taken and, where it can, what is wrong") {
  const std::string taken =
      "expected Unix milliseconds (1796637600000) or a UTC time in ISO 8601 "
      "(2026-12-07T10:00:00Z; seconds and milliseconds optional, or a date alone)";
  CHECK(error_of("") == "an empty time: " + taken);
  CHECK(error_of("yesterday") == "\"yesterday\" is not a time: " + taken);
  CHECK(error_of("2026-12-07T10:00:00") ==
        "\"2026-12-07T10:00:00\" is not a time: no time zone: end it with Z (UTC): " + taken);
  CHECK(error_of("2026-12-07T10:00:00+01:00").find("UTC only: end it with Z") !=
        std::string::npos);
  CHECK(error_of("2026-02-30T00:00Z").find("2026-02-30 is not a date") != std::string::npos);
  CHECK(error_of("2026-12-07T24:00Z").find("hour 24 is out of range") != std::string::npos);
  CHECK(error_of("2026-12-07T10:60Z").find("minute 60 is out of range") != std::string::npos);
  CHECK(error_of("2026-12-07T10:00:60Z").find("second 60 is out of range") != std::string::npos);
  CHECK(error_of("2026-12-07T10:00:00.Z").find("a fraction of 1 to 9 digits") !=
        std::string::npos);
  CHECK(error_of("12345678901234567").find("too many digits") != std::string::npos);
  for (const char* other : {"-5", "2026-12-07 10:00Z", "2026-12-07T10Z", "2026-12-07T10:00:00ZZ",
                            "2026-12-7", "1796637600000.5", "20261207T100000Z"})
    CHECK(error_of(other).find("is not a time") != std::string::npos);
  // What a client sent comes back short and printable.
  const std::string long_value = std::string("\x1b[2J") + std::string(60, 'a');
  CHECK(error_of(long_value).rfind("\"?[2J" + std::string(36, 'a') + "...\" is not a time", 0) ==
        0);
}
