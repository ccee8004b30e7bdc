// parse_time_query() of monitoring/history_csv.h: a `from` or `to` value read strictly, with
// the reason when it is not a time.
#include <optional>
#include <string>

#include "monitoring/history_csv.h"
#include "monitoring/utc_time.h"

namespace tiltgate::monitoring {

namespace {

constexpr const char* kTakenText =
    "expected Unix milliseconds (1796637600000) or a UTC time in ISO 8601 "
    "(2026-12-07T10:00:00Z; seconds and milliseconds optional, or a date alone)";
// Unix milliseconds up to the year 9999 have 15 digits: more cannot be meant (and would
// overflow).
constexpr std::size_t kMaxUnixMsDigits = 15;

// The value as an error message shows it: short, printable, whatever a client sent.
std::string quoted(std::string_view text) {
  std::string out = "\"";
  for (std::size_t i = 0; i < text.size() && i < 40; ++i)
    out += (text[i] >= 0x20 && text[i] < 0x7f) ? text[i] : '?';
  return out + (text.size() > 40 ? "...\"" : "\"");
}

// Reads `count` digits at `at` as a number; none when one is not a digit (or missing).
std::optional<int> query_digits(std::string_view text, std::size_t at, std::size_t count) {
  if (at + count > text.size()) return std::nullopt;
  int value = 0;
  for (std::size_t i = at; i < at + count; ++i) {
    if (text[i] < '0' || text[i] > '9') return std::nullopt;
    value = value * 10 + (text[i] - '0');
  }
  return value;
}

Unexpected<std::string> not_a_time(std::string_view text, const std::string& why = {}) {
  return Unexpected(quoted(text) + " is not a time" + (why.empty() ? "" : ": " + why) + ": " +
                    kTakenText);
}

Expected<std::int64_t, std::string> unix_ms_query(std::string_view text) {
  if (text.size() > kMaxUnixMsDigits) return not_a_time(text, "too many digits");
  std::int64_t value = 0;
  for (const char c : text) value = value * 10 + (c - '0');
  return value;
}

// The time of day after a date's 'T': HH:MM[:SS[.fraction]]Z, as milliseconds.
Expected<std::int64_t, std::string> time_of_day_ms(std::string_view text, std::string_view all) {
  const auto hour = query_digits(text, 0, 2);
  const auto minute = query_digits(text, 3, 2);
  if (!hour || !minute || text[2] != ':') return not_a_time(all);
  if (*hour > 23) return not_a_time(all, "hour " + std::to_string(*hour) + " is out of range");
  if (*minute > 59)
    return not_a_time(all, "minute " + std::to_string(*minute) + " is out of range");
  std::int64_t ms = (*hour * 60LL + *minute) * 60'000;
  std::size_t at = 5;
  if (at < text.size() && text[at] == ':') {
    const auto second = query_digits(text, at + 1, 2);
    if (!second) return not_a_time(all);
    if (*second > 59)
      return not_a_time(all, "second " + std::to_string(*second) + " is out of range");
    ms += *second * 1000LL;
    at += 3;
    if (at < text.size() && text[at] == '.') {
      std::size_t digits = 0;
      int fraction_ms = 0;
      for (++at; at < text.size() && text[at] >= '0' && text[at] <= '9'; ++at, ++digits)
        if (digits < 3) fraction_ms = fraction_ms * 10 + (text[at] - '0');
      if (digits == 0 || digits > 9) return not_a_time(all, "a fraction of 1 to 9 digits");
      for (std::size_t i = digits; i < 3; ++i) fraction_ms *= 10;
      ms += fraction_ms;
    }
  }
  const std::string_view zone = text.substr(at);
  if (zone == "Z") return ms;
  if (zone.empty()) return not_a_time(all, "no time zone: end it with Z (UTC)");
  if (zone[0] == '+' || zone[0] == '-') return not_a_time(all, "UTC only: end it with Z");
  return not_a_time(all);
}

}  // namespace

Expected<std::int64_t, std::string> parse_time_query(std::string_view text) {
  if (text.empty()) return Unexpected(std::string("an empty time: ") + kTakenText);
  if (text.find_first_not_of("0123456789") == std::string_view::npos) return unix_ms_query(text);
  const auto year = query_digits(text, 0, 4);
  const auto month = query_digits(text, 5, 2);
  const auto day_of_month = query_digits(text, 8, 2);
  if (!year || !month || !day_of_month || text[4] != '-' || text[7] != '-')
    return not_a_time(text);
  const auto day = civil_day(*year, static_cast<unsigned>(*month),
                             static_cast<unsigned>(*day_of_month));
  if (!day) return not_a_time(text, std::string(text.substr(0, 10)) + " is not a date");
  if (text.size() == 10) return day_start_unix_ms(*day);
  if (text[10] != 'T') return not_a_time(text);
  auto time = time_of_day_ms(text.substr(11), text);
  if (!time) return Unexpected(time.error());
  return day_start_unix_ms(*day) + *time;
}

}  // namespace tiltgate::monitoring
