// Reading a store's records without opening it (record_store.h): for a command that shows what
// a running gateway keeps (`tiltgate audit`), or keeps after it stopped. Reads only: it cuts
// nothing and moves no cursor, so it is safe beside the gateway appending to the same
// directory; a record being written at that moment (cut short) ends its segment's reading,
// as a torn one would.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "store/record_frame.h"

namespace tiltgate::store {

// One segment file's records as read_segments() found them.
struct SegmentRecords {
  std::uint64_t id = 0;  // its number: 1 for a store's first
  std::string name;      // its file name
  std::vector<Record> records;  // its whole records up to `damage`
  // Where its reading stopped short of its end, and why ("at byte 1234: a corrupt record"):
  // a record damaged, or cut short by a crash or a hand.
  std::optional<std::string> damage;
};

// The segment files of `dir` in append order (not yet a segment, as one being created: left
// out), each read up to its first record that is not whole and valid.
Expected<std::vector<SegmentRecords>, std::string> read_segments(const std::filesystem::path& dir);

// Every whole record of the segment files in `dir`, in append order, replayed or not. A
// segment is read up to its first record that is not whole and valid. Fails when `dir` cannot
// be listed or a segment cannot be read.
Expected<std::vector<Record>, std::string> read_records(const std::filesystem::path& dir);

}  // namespace tiltgate::store
