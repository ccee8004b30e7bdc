#include "monitoring/utc_time.h"

#include <fmt/format.h>

#include <chrono>

namespace tiltgate::monitoring {

namespace {

using Ms = std::chrono::milliseconds;

std::chrono::sys_days as_sys_days(std::int64_t day) {
  return std::chrono::sys_days{std::chrono::days(day)};
}

bool two_digits(std::string_view text, std::size_t at, unsigned& out) {
  if (text[at] < '0' || text[at] > '9' || text[at + 1] < '0' || text[at + 1] > '9') return false;
  out = static_cast<unsigned>((text[at] - '0') * 10 + (text[at + 1] - '0'));
  return true;
}

}  // namespace

std::int64_t utc_day(std::int64_t unix_ms) {
  const std::chrono::sys_time<Ms> time{Ms(unix_ms)};
  return std::chrono::floor<std::chrono::days>(time).time_since_epoch().count();
}

std::string utc_date_text(std::int64_t day) {
  const std::chrono::year_month_day date{as_sys_days(day)};
  return fmt::format("{:04}-{:02}-{:02}", int(date.year()), unsigned(date.month()),
                     unsigned(date.day()));
}

std::optional<std::int64_t> civil_day(int year, unsigned month, unsigned day) {
  const std::chrono::year_month_day date{std::chrono::year(year), std::chrono::month(month),
                                         std::chrono::day(day)};
  if (!date.ok()) return std::nullopt;
  return std::chrono::sys_days(date).time_since_epoch().count();
}

std::optional<std::int64_t> parse_utc_date(std::string_view text) {
  if (text.size() != 10 || text[4] != '-' || text[7] != '-') return std::nullopt;
  unsigned century = 0;
  unsigned year = 0;
  unsigned month = 0;
  unsigned day = 0;
  if (!two_digits(text, 0, century) || !two_digits(text, 2, year) || !two_digits(text, 5, month) ||
      !two_digits(text, 8, day))
    return std::nullopt;
  return civil_day(static_cast<int>(century * 100 + year), month, day);
}

std::string utc_timestamp(std::int64_t unix_ms) {
  const std::chrono::sys_time<Ms> time{Ms(unix_ms)};
  const auto day = std::chrono::floor<std::chrono::days>(time);
  const std::chrono::year_month_day date{day};
  const std::chrono::hh_mm_ss<Ms> clock{time - day};
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}.{:03}Z", int(date.year()),
                     unsigned(date.month()), unsigned(date.day()), clock.hours().count(),
                     clock.minutes().count(), clock.seconds().count(),
                     clock.subseconds().count());
}

}  // namespace tiltgate::monitoring
