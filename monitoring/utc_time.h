// UTC calendar arithmetic for the long record: the day a time falls on (a record file holds one
// UTC day, named by its date) and the text of a time (the CSV's `time` column). Pure; the civil
// calendar is std::chrono's (proleptic Gregorian, no leap seconds, as Unix time).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace tiltgate::monitoring {

inline constexpr std::int64_t kDayMs = 86'400'000;

// Days since 1970-01-01 of the UTC day that holds `unix_ms` (negative before 1970).
std::int64_t utc_day(std::int64_t unix_ms);
inline std::int64_t day_start_unix_ms(std::int64_t day) { return day * kDayMs; }

// "2026-12-07" for the day's number.
std::string utc_date_text(std::int64_t day);
// The day's number for a date "YYYY-MM-DD" (four-digit year); none for any other text or a
// date that does not exist (2026-02-30).
std::optional<std::int64_t> parse_utc_date(std::string_view text);
// The day's number for a year, month (1..12) and day of month; none for a date that does not
// exist.
std::optional<std::int64_t> civil_day(int year, unsigned month, unsigned day);

// "2026-12-07T10:00:00.000Z" for a Unix time in milliseconds.
std::string utc_timestamp(std::int64_t unix_ms);

}  // namespace tiltgate::monitoring
