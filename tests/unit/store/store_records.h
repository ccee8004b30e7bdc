// Numbered records and small stores for the store's tests (store/record_store.h): budgets and
// segments are small so that a few records fill them.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "store/record_store.h"

namespace tiltgate::test {

using store::Record;
using store::RecordStore;
using store::StoreOptions;

// Record i: 8 + 12 + 8 + 16 = 44 bytes on disk.
inline Record record(int i) {
  char topic[9];
  std::snprintf(topic, sizeof topic, "t/%06d", i);
  std::vector<std::uint8_t> payload(16, static_cast<std::uint8_t>(i));
  return Record{topic, payload, 1796176370000 + i, static_cast<std::uint8_t>(i % 3)};
}
constexpr std::uint64_t kRecordBytes = 44;
constexpr std::uint64_t kSegmentHeader = 8;

// Segments of 8 + 5 records (228 bytes), a budget of 4 of them.
inline StoreOptions small() {
  StoreOptions o;
  o.segment_bytes = kSegmentHeader + 5 * kRecordBytes;
  o.budget_bytes = 4 * o.segment_bytes;
  o.sync_every = 4;
  return o;
}

inline RecordStore open_store(const std::filesystem::path& dir, StoreOptions o = small()) {
  auto store = RecordStore::open(dir, o);
  REQUIRE(store.has_value());
  return std::move(*store);
}

inline void append(RecordStore& store, int from, int to) {
  for (int i = from; i < to; ++i) REQUIRE(store.append(record(i)).has_value());
}

inline std::vector<int> numbers(const std::vector<Record>& records) {
  std::vector<int> out;
  for (const Record& r : records) out.push_back(std::stoi(r.topic.substr(2)));
  return out;
}

inline std::vector<int> range(int from, int to) {
  std::vector<int> out;
  for (int i = from; i < to; ++i) out.push_back(i);
  return out;
}

inline std::vector<std::filesystem::path> segments(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() == ".seg") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

inline std::vector<Record> everything(RecordStore& store) { return store.peek(1000000).value(); }

}  // namespace tiltgate::test
