// The long record on a disk that refuses (monitoring/long_record.h, "A disk that refuses"): a
// directory that cannot be made, one mounted read-only, a disk full (a real tmpfs of its own,
// tests/unit/support/small_disk.h). Nothing throws into the owner, every failure is counted,
// what is refused is held in memory within its bound and written out, in order, once the disk
// takes it; the fault's start and end are one notice each.
#include <doctest/doctest.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "monitoring/long_record.h"
#include "unit/monitoring/record_fixtures.h"
#include "unit/support/scratch_dir.h"
#include "unit/support/small_disk.h"

using namespace tiltgate::monitoring;
using namespace tiltgate::test;
namespace fs = std::filesystem;

namespace {

constexpr int kMinutesADay = 1440;

// The problem notices and the recoveries among `notices`.
std::pair<int, int> problems_and_ends(const std::vector<RecordNotice>& notices) {
  int problems = 0;
  for (const RecordNotice& n : notices) problems += n.problem ? 1 : 0;
  return {problems, static_cast<int>(notices.size()) - problems};
}

// A directory the gateway cannot write: a tmpfs remounted read-only as root (root writes through
// a mode of 0555), its mode 0555 otherwise.
class ReadOnlyDirectory {
 public:
  ReadOnlyDirectory() {
    if (::geteuid() != 0) {
      dir_ = scratch_.path("record");
      fs::create_directories(dir_);
      ::chmod(dir_.c_str(), 0555);
      ready_ = true;
      return;
    }
    if (!disk_.available()) return;
    dir_ = disk_.path("record");
    fs::create_directories(dir_);
    ready_ = remount(MS_RDONLY);
  }
  ~ReadOnlyDirectory() { make_writable(); }

  bool ready() const { return ready_; }
  const fs::path& path() const { return dir_; }
  void make_writable() {
    if (!ready_) return;
    if (::geteuid() != 0)
      ::chmod(dir_.c_str(), 0755);
    else
      remount(0);
  }

 private:
  bool remount(unsigned long flags) {
    return ::mount(nullptr, disk_.path("").c_str(), nullptr, MS_REMOUNT | flags, nullptr) == 0;
  }

  ScratchDir scratch_;
  SmallDisk disk_;
  fs::path dir_;
  bool ready_ = false;
};

}  // namespace

TEST_CASE("a record whose directory cannot be made opens anyway, holds its intervals, and writes them out once it can") {
  ScratchDir scratch;
  const fs::path blocker = scratch.path("state");
  std::ofstream(blocker) << "a file where the state directory should be";
  const fs::path dir = blocker / "record" / "boom";
  auto record = LongRecord::open(dir);
  REQUIRE(record.disk_fault().has_value());
  CHECK(record.disk_fault()->find("cannot create") != std::string::npos);
  CHECK(record.append(interval(0)) == LongRecord::Appended::held);
  CHECK(record.append(interval(1)) == LongRecord::Appended::held);
  record.sync();
  CHECK(record.held() == 2);
  CHECK(record.written_until() == kDec7 + 2 * kMinute);
  CHECK(record.disk_failures() == 4);  // open, two appends, the sync: each tried the disk once
  CHECK(record.remove_expired(kDec7) == 0);
  CHECK(problems_and_ends(record.take_notices()) == std::pair{1, 0});  // said once

  fs::remove(blocker);
  record.sync();
  CHECK(record.held() == 0);
  CHECK_FALSE(record.disk_fault().has_value());
  const auto notices = record.take_notices();
  CHECK(problems_and_ends(notices) == std::pair{0, 1});
  CHECK(notices.at(0).text.find("takes intervals again") != std::string::npos);
  CHECK(numbers(everything(dir)) == range(0, 2));
  CHECK(record.append(interval(2)) == LongRecord::Appended::written);
}

TEST_CASE("a read-only directory: nothing throws, appends are held and counted, and written out in order once it takes writes") {
  ReadOnlyDirectory readonly;
  if (!readonly.ready()) {
    MESSAGE("needs root for a tmpfs to remount read-only: skipped");
    return;
  }
  auto record = LongRecord::open(readonly.path());
  CHECK_FALSE(record.disk_fault().has_value());  // it can be read: nothing to say yet
  for (int i = 0; i < 4; ++i) CHECK(record.append(interval(i)) == LongRecord::Appended::held);
  CHECK(record.held() == 4);
  CHECK(record.disk_failures() == 4);
  CHECK(record.appended() == 0);
  CHECK(problems_and_ends(record.take_notices()) == std::pair{1, 0});
  CHECK(everything(readonly.path()).empty());

  readonly.make_writable();
  CHECK(record.append(interval(4)) == LongRecord::Appended::written);
  CHECK(record.held() == 0);
  CHECK(record.appended() == 5);
  CHECK(problems_and_ends(record.take_notices()) == std::pair{0, 1});
  CHECK(numbers(everything(readonly.path())) == range(0, 5));
}

TEST_CASE("a full disk: intervals held up to hold_max, the oldest then lost and counted, the rest written out once there is room") {
  SmallDisk disk;
  if (no_small_disk(disk)) return;
  LongRecordOptions options;
  options.hold_max = 5;
  auto record = LongRecord::open(disk.path("record"), options);
  append(record, 0, 2);
  disk.fill();
  // One interval a day: each needs a new file, and a full disk gives it no block.
  for (int day = 1; day <= 10; ++day)
    CHECK(record.append(interval(day * kMinutesADay)) == LongRecord::Appended::held);
  CHECK(record.held() == 5);
  CHECK(record.lost() == 5);
  CHECK(record.disk_fault().has_value());
  CHECK(problems_and_ends(record.take_notices()) == std::pair{2, 0});  // refusing; losing

  disk.free();
  record.sync();
  CHECK(record.held() == 0);
  const auto notices = record.take_notices();
  REQUIRE(problems_and_ends(notices) == std::pair{0, 1});
  CHECK(notices[0].text.find("5 intervals were lost") != std::string::npos);
  std::vector<int> expected = range(0, 2);
  for (int day = 6; day <= 10; ++day) expected.push_back(day * kMinutesADay);
  CHECK(numbers(everything(disk.path("record"))) == expected);
}
