// The store on a disk that refuses (store/record_store.h, "A disk that refuses"): a real tmpfs
// of its own filled to ENOSPC (tests/unit/support/small_disk.h), and directories where the
// store's files should be. Whatever the disk does, nothing is resent in a loop, nothing is lost
// uncounted, and the store goes back to the disk by itself once it has room.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>

#include "store/record_store.h"
#include "unit/store/store_records.h"
#include "unit/support/small_disk.h"

using namespace tiltgate::store;
using namespace tiltgate::test;
namespace fs = std::filesystem;

namespace {

// The problem notices and the recoveries among `notices`.
std::pair<int, int> count(const std::vector<StoreNotice>& notices) {
  int problems = 0;
  for (const StoreNotice& n : notices) problems += n.problem ? 1 : 0;
  return {problems, static_cast<int>(notices.size()) - problems};
}

// A store on `disk` holding records 0..on_disk-1, then the disk filled.
RecordStore store_on_full_disk(SmallDisk& disk, int on_disk) {
  auto store = open_store(disk.path("store"));
  append(store, 0, on_disk);
  disk.fill();
  return store;
}

}  // namespace

TEST_CASE("a store whose disk fills keeps what it refuses in memory, in order, and writes it out once there is room") {
  SmallDisk disk;
  if (no_small_disk(disk)) return;
  auto store = store_on_full_disk(disk, 3);
  append(store, 3, 12);  // segments 2 and 3 cannot be made: 5..11 wait in memory
  CHECK(store.disk_fault().has_value());
  CHECK(store.in_memory() >= 7);
  CHECK(store.records() == 12);
  CHECK(store.dropped() == 0);
  CHECK(numbers(everything(store)) == range(0, 12));
  REQUIRE(store.sync().has_value());  // still full: nothing changes, nothing said again
  CHECK(count(store.take_notices()) == std::pair{1, 0});

  disk.free();
  REQUIRE(store.sync().has_value());
  CHECK_FALSE(store.disk_fault().has_value());
  CHECK(store.in_memory() == 0);
  const auto notices = store.take_notices();
  CHECK(count(notices) == std::pair{0, 1});
  CHECK(notices.at(0).text.find("written out") != std::string::npos);
  auto reopened = open_store(disk.path("store"));
  CHECK(numbers(everything(reopened)) == range(0, 12));
}

TEST_CASE("with the disk full, a store over its budget drops its oldest records first, each counted") {
  SmallDisk disk;
  if (no_small_disk(disk)) return;
  auto store = store_on_full_disk(disk, 10);  // two segments on disk
  append(store, 10, 40);  // in memory, over the budget of 20 records
  CHECK(store.records() <= 20);
  CHECK(store.dropped() == 40 - store.records());
  const auto kept = numbers(everything(store));
  REQUIRE_FALSE(kept.empty());
  CHECK(kept == range(40 - static_cast<int>(kept.size()), 40));  // the newest, in order
}

TEST_CASE("a replay whose cursor the full disk refuses goes on from its place in memory, and saves it once there is room") {
  SmallDisk disk;
  if (no_small_disk(disk)) return;
  {
    auto store = store_on_full_disk(disk, 14);
    CHECK(numbers(store.peek(4).value()) == range(0, 4));
    REQUIRE(store.pop(4).has_value());
    CHECK(numbers(store.peek(4).value()) == range(4, 8));  // not 0..3 again
    REQUIRE(store.pop(4).has_value());
    CHECK(numbers(store.peek(100).value()) == range(8, 14));
    CHECK(store.replayed() == 8);
    CHECK(store.disk_fault().has_value());
    CHECK(count(store.take_notices()) == std::pair{1, 0});  // said once
    disk.free();
    REQUIRE(store.sync().has_value());
    CHECK_FALSE(store.disk_fault().has_value());
    CHECK(count(store.take_notices()) == std::pair{0, 1});
  }
  auto reopened = open_store(disk.path("store"));  // the place was saved once there was room
  CHECK(numbers(everything(reopened)) == range(8, 14));
}

TEST_CASE("an empty directory where the cursor should be is removed, and the store opens and replays from the oldest") {
  SmallDisk disk;  // any directory would do; the tmpfs is a scratch one
  const fs::path dir = disk.available() ? disk.path("store")
                                        : fs::temp_directory_path() / "tiltgate-store-cursor-dir";
  fs::remove_all(dir);
  {
    auto store = open_store(dir);
    append(store, 0, 6);
    REQUIRE(store.pop(2).has_value());
  }
  fs::remove(dir / "cursor");
  fs::create_directory(dir / "cursor");
  {
    auto store = open_store(dir);
    CHECK(numbers(everything(store)) == range(0, 6));  // at least once: from the oldest
    REQUIRE_FALSE(store.repairs().empty());
    CHECK(store.repairs()[0] == "cursor: an empty directory in the file's place, removed");
    REQUIRE(store.pop(3).has_value());  // the cursor can be written again
  }
  auto reopened = open_store(dir);
  CHECK(numbers(everything(reopened)) == range(3, 6));
  fs::remove_all(dir);
}

TEST_CASE("a directory with files where a segment should be is moved aside, its files kept, and the other segments open") {
  SmallDisk disk;
  const fs::path dir = disk.available() ? disk.path("store")
                                        : fs::temp_directory_path() / "tiltgate-store-seg-dir";
  fs::remove_all(dir);
  {
    auto store = open_store(dir);
    append(store, 0, 7);  // segments 1 (0-4) and 2 (5, 6)
  }
  const fs::path second = segments(dir).at(1);
  fs::remove(second);
  fs::create_directory(second);
  std::ofstream(second / "someone's.txt") << "keep me\n";
  auto store = open_store(dir);
  CHECK(numbers(everything(store)) == range(0, 5));
  REQUIRE(store.repairs().size() == 1);
  CHECK(store.repairs()[0] == second.filename().string() +
                                  ": a directory in the file's place, moved to " +
                                  second.filename().string() + ".moved-aside");
  CHECK(fs::exists(dir / (second.filename().string() + ".moved-aside") / "someone's.txt"));
  append(store, 7, 9);  // appends go on
  CHECK(numbers(everything(store)) == std::vector<int>{0, 1, 2, 3, 4, 7, 8});
  fs::remove_all(dir);
}
