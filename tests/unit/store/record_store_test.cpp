// The store-and-forward on disk (store/record_store.h): order, the replay cursor across
// restarts, the byte budget, and what a torn or corrupted file costs. Budgets and segments are
// small here so that a few records fill them.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "store/record_store.h"
#include "unit/store/store_records.h"

using namespace tiltgate::store;
using namespace tiltgate::test;
namespace fs = std::filesystem;

namespace {

// A scratch state_dir, removed at the end.
struct StateDir {
  StateDir() {
    std::string pattern = (fs::temp_directory_path() / "tiltgate-store-XXXXXX").string();
    REQUIRE(::mkdtemp(pattern.data()) != nullptr);
    path = pattern;
  }
  ~StateDir() { fs::remove_all(path); }
  fs::path path;
};

}  // namespace

TEST_CASE("records come back in append order, whole, and again after a reopen") {
  StateDir dir;
  {
    auto store = open_store(dir.path);
    append(store, 0, 12);
    CHECK(store.records() == 12);
    CHECK(store.bytes() == 3 * kSegmentHeader + 12 * kRecordBytes);  // segments of 5, 5, 2
    const auto all = everything(store);
    CHECK(numbers(all) == range(0, 12));
    CHECK(all[7] == record(7));
  }
  auto store = open_store(dir.path);
  CHECK(store.records() == 12);
  CHECK(numbers(everything(store)) == range(0, 12));
  CHECK(store.repairs().empty());
  CHECK(segments(dir.path).size() == 3);
}

TEST_CASE("peek gives the oldest records and pop moves past them: a batch at a time") {
  StateDir dir;
  auto store = open_store(dir.path);
  append(store, 0, 12);
  CHECK(numbers(store.peek(4).value()) == range(0, 4));
  CHECK(numbers(store.peek(4).value()) == range(0, 4));  // not popped: the same again
  REQUIRE(store.pop(4).has_value());
  CHECK(numbers(store.peek(4).value()) == range(4, 8));
  REQUIRE(store.pop(4).has_value());
  CHECK(store.records() == 4);
  CHECK(store.replayed() == 8);
  append(store, 12, 14);  // appends while the replay runs come after it
  CHECK(numbers(everything(store)) == range(8, 14));
}

TEST_CASE("a restart in the middle of a replay does not replay again what was popped") {
  StateDir dir;
  {
    auto store = open_store(dir.path);
    append(store, 0, 12);
    REQUIRE(store.pop(3).has_value());  // inside the first segment
  }
  {
    auto store = open_store(dir.path);
    CHECK(store.records() == 9);
    CHECK(numbers(store.peek(2).value()) == std::vector<int>{3, 4});
    REQUIRE(store.pop(4).has_value());  // across into the second segment
  }
  auto store = open_store(dir.path);
  CHECK(numbers(everything(store)) == range(7, 12));
  CHECK(store.replayed() == 0);  // counted since this open
}

TEST_CASE("records peeked but not popped before a crash are given again: delivery is at least once") {
  StateDir dir;
  {
    auto store = open_store(dir.path);
    append(store, 0, 6);
    CHECK(numbers(store.peek(3).value()) == range(0, 3));  // published, then the process died
  }
  auto store = open_store(dir.path);
  CHECK(numbers(store.peek(3).value()) == range(0, 3));
}

TEST_CASE("segments replayed to their end are deleted, the one appended to as well once drained") {
  StateDir dir;
  auto store = open_store(dir.path);
  append(store, 0, 12);
  REQUIRE(store.pop(5).has_value());
  CHECK(segments(dir.path).size() == 2);
  CHECK(store.bytes() == 2 * kSegmentHeader + 7 * kRecordBytes);
  REQUIRE(store.pop(100).has_value());
  CHECK(segments(dir.path).empty());
  CHECK(store.records() == 0);
  CHECK(store.bytes() == 0);
  CHECK(store.replayed() == 12);
  append(store, 12, 13);  // a new segment after the drained ones
  auto reopened = open_store(dir.path);
  CHECK(numbers(everything(reopened)) == std::vector<int>{12});
}

TEST_CASE("a store drained, restarted, and appended to keeps what comes after the drain") {
  StateDir dir;
  {
    auto store = open_store(dir.path);
    append(store, 0, 7);
    REQUIRE(store.pop(7).has_value());
  }
  {
    auto store = open_store(dir.path);  // no segment left, the cursor past all of them
    CHECK(store.records() == 0);
    append(store, 7, 9);
  }
  auto store = open_store(dir.path);
  CHECK(numbers(everything(store)) == std::vector<int>{7, 8});
}

TEST_CASE("a full store drops its oldest whole segment and counts the records in it") {
  StateDir dir;
  auto store = open_store(dir.path);
  append(store, 0, 20);  // four full segments: the budget
  CHECK(store.bytes() == small().budget_bytes);
  CHECK(store.dropped() == 0);
  REQUIRE(store.append(record(20)).has_value());  // needs a fifth segment: the first goes
  CHECK(store.dropped() == 5);
  CHECK(store.records() == 16);
  CHECK(store.bytes() <= small().budget_bytes);
  CHECK(numbers(everything(store)) == range(5, 21));
  CHECK(segments(dir.path).size() == 4);
  auto reopened = open_store(dir.path);  // the drop holds after a restart
  CHECK(numbers(everything(reopened)) == range(5, 21));
}

TEST_CASE("a drop counts only the records of the segment not yet replayed") {
  StateDir dir;
  auto store = open_store(dir.path);
  append(store, 0, 20);
  REQUIRE(store.pop(2).has_value());
  REQUIRE(store.append(record(20)).has_value());
  CHECK(store.dropped() == 3);
  CHECK(numbers(store.peek(1).value()) == std::vector<int>{5});
  // A restart with the cursor still naming the dropped segment starts at the oldest kept.
  auto reopened = open_store(dir.path);
  CHECK(numbers(everything(reopened)) == range(5, 21));
}

TEST_CASE("a file cut inside its last record opens and loses that record only, at every cut") {
  StateDir dir;
  {
    auto store = open_store(dir.path);
    append(store, 0, 8);  // segment 1: 0-4, segment 2: 5-7
  }
  const fs::path last = segments(dir.path).back();
  const std::uint64_t whole = kSegmentHeader + 3 * kRecordBytes;
  REQUIRE(fs::file_size(last) == whole);
  const auto original = fs::temp_directory_path() / (last.filename().string() + ".orig");
  fs::copy_file(last, original, fs::copy_options::overwrite_existing);
  for (std::uint64_t cut = whole - kRecordBytes; cut < whole; ++cut) {
    CAPTURE(cut);
    fs::copy_file(original, last, fs::copy_options::overwrite_existing);
    fs::resize_file(last, cut);
    auto store = open_store(dir.path);
    CHECK(store.records() == 7);
    CHECK(numbers(everything(store)) == range(0, 7));
    if (cut > whole - kRecordBytes) {
      REQUIRE(store.repairs().size() == 1);
      CHECK(store.repairs()[0].find("a record cut short") != std::string::npos);
    }
    CHECK(fs::file_size(last) == whole - kRecordBytes);  // the torn tail is gone
  }
  fs::remove(original);
}

TEST_CASE("after a torn tail, appends go on after the last whole record") {
  StateDir dir;
  {
    auto store = open_store(dir.path);
    append(store, 0, 3);
  }
  fs::resize_file(segments(dir.path).back(), kSegmentHeader + 2 * kRecordBytes + 10);
  {
    auto store = open_store(dir.path);
    append(store, 3, 5);
  }
  auto store = open_store(dir.path);
  CHECK(numbers(everything(store)) == std::vector<int>{0, 1, 3, 4});
  CHECK(store.repairs().empty());
}

TEST_CASE("a segment cut inside its header (a crash as it was made) is removed, the rest opens") {
  StateDir dir;
  {
    auto store = open_store(dir.path);
    append(store, 0, 5);
  }
  std::ofstream(dir.path / "00000000000000000002.seg", std::ios::binary).write("tgst", 4);
  auto store = open_store(dir.path);
  CHECK(numbers(everything(store)) == range(0, 5));
  CHECK(segments(dir.path).size() == 1);
}

TEST_CASE("a corrupted CRC in the middle of a segment stops that segment at the last good record before it") {
  StateDir dir;
  {
    auto store = open_store(dir.path);
    append(store, 0, 12);  // segments 0-4, 5-9, 10-11
  }
  const fs::path second = segments(dir.path).at(1);
  {
    std::fstream file(second, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(kSegmentHeader + 2 * kRecordBytes + 30));  // record 7
    file.put('\x55');
  }
  auto store = open_store(dir.path);
  // Records 7, 8 and 9 are lost (the lengths after a bad record cannot be trusted); the other
  // segments are whole.
  CHECK(numbers(everything(store)) == std::vector<int>{0, 1, 2, 3, 4, 5, 6, 10, 11});
  REQUIRE(store.repairs().size() == 1);
  CHECK(store.repairs()[0] ==
        "00000000000000000002.seg: cut at byte 96: a corrupt record, 3 records lost");
  CHECK(store.lost() == 3);
  CHECK(store.dropped() == 0);
}

TEST_CASE("a record found corrupt while replaying drops the rest of its segment, counted as lost and said") {
  StateDir dir;
  auto store = open_store(dir.path);
  append(store, 0, 10);
  {
    std::fstream file(segments(dir.path).at(0), std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(kSegmentHeader + 3 * kRecordBytes + 25));  // record 3
    file.put('\x55');
  }
  CHECK(numbers(everything(store)) == std::vector<int>{0, 1, 2, 5, 6, 7, 8, 9});
  CHECK(store.lost() == 2);
  CHECK(store.dropped() == 0);
  CHECK(store.records() == 8);
  const auto notices = store.take_notices();
  REQUIRE(notices.size() == 1);
  CHECK(notices[0].problem);
  CHECK(notices[0].text.find("2 records lost") != std::string::npos);
}

TEST_CASE("a record larger than a segment is refused, and the store stays as it was") {
  StateDir dir;
  auto store = open_store(dir.path);
  append(store, 0, 2);
  Record big = record(99);
  big.payload.resize(small().segment_bytes);
  const auto refused = store.append(big);
  REQUIRE_FALSE(refused.has_value());
  CHECK(refused.error().find("does not fit") != std::string::npos);
  CHECK(numbers(everything(store)) == std::vector<int>{0, 1});
}

TEST_CASE("an unreadable cursor replays from the oldest record rather than losing any") {
  StateDir dir;
  {
    auto store = open_store(dir.path);
    append(store, 0, 6);
    REQUIRE(store.pop(2).has_value());
  }
  std::ofstream(dir.path / "cursor", std::ios::binary | std::ios::trunc).write("junk", 4);
  auto store = open_store(dir.path);
  CHECK(numbers(everything(store)) == range(0, 6));
  CHECK(store.repairs().at(0).find("cursor") == 0);
}

TEST_CASE("a budget too small for a segment is refused at open") {
  StateDir dir;
  StoreOptions o;
  o.budget_bytes = 100;
  CHECK_FALSE(RecordStore::open(dir.path, o).has_value());
}

TEST_CASE("the defaults: a 64 MiB budget in 4 MiB segments, synced every 64 appends") {
  const StoreOptions o;
  CHECK(o.budget_bytes == 64u * 1024 * 1024);
  CHECK(o.segment_bytes == 4u * 1024 * 1024);
  CHECK(o.sync_every == 64);
}
