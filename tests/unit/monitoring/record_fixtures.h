// Numbered intervals and scratch records for the long record's tests (monitoring/long_record.h):
// interval i starts i minutes after 2026-12-07T00:00:00Z and carries values made from i, so a
// test reads back which intervals it got.
#pragma once

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "monitoring/long_record.h"
#include "monitoring/long_record_reader.h"

namespace tiltgate::test {

inline constexpr std::int64_t kDec7 = 1796601600000;  // 2026-12-07T00:00:00.000Z
inline constexpr std::int64_t kMinute = 60'000;

inline monitoring::IntervalRecord interval(int i) {
  monitoring::IntervalRecord r;
  r.start_unix_ms = kDec7 + i * kMinute;
  r.length_ms = kMinute;
  r.samples = 60;
  r.unsynchronised = static_cast<std::uint32_t>(i % 2);
  r.x = {static_cast<float>(i) - 0.5f, static_cast<float>(i), static_cast<float>(i) + 0.5f};
  r.tilt = {1.0f, 2.0f, 3.0f};  // y and temperature: none, as a single-axis sensor's
  return r;
}

// The numbers of `records` (interval(i) has x.mean i).
inline std::vector<int> numbers(const std::vector<monitoring::IntervalRecord>& records) {
  std::vector<int> out;
  for (const auto& r : records) out.push_back(static_cast<int>(std::lround(r.x.mean)));
  return out;
}

inline std::vector<int> range(int from, int to) {
  std::vector<int> out;
  for (int i = from; i < to; ++i) out.push_back(i);
  return out;
}

inline void append(monitoring::LongRecord& record, int from, int to) {
  for (int i = from; i < to; ++i)
    REQUIRE(record.append(interval(i)) == monitoring::LongRecord::Appended::written);
}

// Everything `reader` gives, a batch of `batch` at a time.
inline std::vector<monitoring::IntervalRecord> read_all(monitoring::LongRecordReader reader,
                                                        std::size_t batch = 7) {
  std::vector<monitoring::IntervalRecord> out;
  for (auto rows = reader.next(batch); !rows.empty(); rows = reader.next(batch)) {
    CHECK(rows.size() <= batch);
    out.insert(out.end(), rows.begin(), rows.end());
  }
  return out;
}

// Every interval of the record in `dir`.
inline std::vector<monitoring::IntervalRecord> everything(const std::filesystem::path& dir) {
  return read_all(monitoring::LongRecordReader(dir, INT64_MIN / 2, INT64_MAX / 2));
}

inline bool equal(const monitoring::ChannelStats& a, const monitoring::ChannelStats& b) {
  const auto same = [](float p, float q) { return (std::isnan(p) && std::isnan(q)) || p == q; };
  return same(a.min, b.min) && same(a.mean, b.mean) && same(a.max, b.max);
}

inline bool equal(const monitoring::IntervalRecord& a, const monitoring::IntervalRecord& b) {
  return a.start_unix_ms == b.start_unix_ms && a.length_ms == b.length_ms &&
         a.samples == b.samples && a.unsynchronised == b.unsynchronised && equal(a.x, b.x) &&
         equal(a.y, b.y) && equal(a.tilt, b.tilt) && equal(a.temperature, b.temperature);
}

}  // namespace tiltgate::test
