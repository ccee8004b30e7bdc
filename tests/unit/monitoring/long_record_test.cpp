// A sensor's long record on disk (monitoring/long_record.h): order, one file per UTC day, time
// ranges, the repairs after a crash, damage skipped and counted, retention by keep_days with the
// clock injected, and the record after a SIGKILL.
#include <doctest/doctest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "monitoring/long_record.h"
#include "monitoring/record_format.h"
#include "monitoring/utc_time.h"
#include "unit/monitoring/record_fixtures.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate::monitoring;
using namespace tiltgate::test;
namespace fs = std::filesystem;

namespace {

constexpr int kDayMinutes = 1440;

fs::path record_dir(const ScratchDir& scratch) { return scratch.path("record/boom"); }

LongRecordOptions keeping(std::uint32_t days) {
  LongRecordOptions options;
  options.keep_days = days;
  return options;
}

void flip_byte(const fs::path& file, std::uint64_t at) {
  std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(static_cast<std::streamoff>(at));
  const char c = static_cast<char>(f.get());
  f.seekp(static_cast<std::streamoff>(at));
  f.put(static_cast<char>(c ^ 0x5a));
}

std::vector<std::string> file_names(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST_CASE("intervals appended come back in order and whole, and again after a reopen") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  {
    auto record = LongRecord::open(dir);
    CHECK_FALSE(record.written_until().has_value());
    append(record, 0, 30);
    CHECK(record.appended() == 30);
    CHECK(record.written_until() == kDec7 + 30 * kMinute);
    const auto all = everything(dir);
    CHECK(numbers(all) == range(0, 30));
    CHECK(equal(all.at(7), interval(7)));
    CHECK(record.take_notices().empty());
  }
  auto record = LongRecord::open(dir);
  CHECK(record.repairs().empty());
  CHECK(record.written_until() == kDec7 + 30 * kMinute);
  append(record, 30, 40);
  CHECK(numbers(everything(dir)) == range(0, 40));
  CHECK(numbers(read_all(record.read(kDec7, kDec7 + kDayMs))) == range(0, 40));
}

TEST_CASE("each interval goes to the file of the UTC day it starts on") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  auto record = LongRecord::open(dir);
  append(record, kDayMinutes - 10, kDayMinutes + 10);  // 23:50 to 00:10 the next day
  CHECK(file_names(dir) == std::vector<std::string>{"2026-12-07.rec", "2026-12-08.rec"});
  CHECK(fs::file_size(dir / "2026-12-07.rec") == records_end(10));
  CHECK(fs::file_size(dir / "2026-12-08.rec") == records_end(10));
}

TEST_CASE("a range gives the intervals that start in it, from included and to excluded, across days, in batches of any size") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  auto record = LongRecord::open(dir);
  append(record, kDayMinutes - 10, kDayMinutes + 10);
  const auto start = [](int i) { return kDec7 + i * kMinute; };
  const int last = kDayMinutes - 5;
  CHECK(numbers(read_all(record.read(start(last), start(last + 10)))) == range(last, last + 10));
  // An interval is in the range by its start: one that started a millisecond before `from` is
  // not, one that starts a millisecond before `to` is.
  CHECK(numbers(read_all(record.read(start(last) + 1, start(last + 10) + 1))) ==
        range(last + 1, last + 11));
  for (std::size_t batch : {1u, 3u, 1000u})
    CHECK(numbers(read_all(record.read(start(last), start(last + 10)), batch)) ==
          range(last, last + 10));
  CHECK(read_all(record.read(start(last), start(last))).empty());      // an empty range
  CHECK(read_all(record.read(start(last + 5), start(last))).empty());  // backwards
  CHECK(read_all(record.read(0, kDec7)).empty());                      // before the record
  CHECK(read_all(record.read(start(5000), start(6000))).empty());      // after it
  CHECK(read_all(LongRecordReader(scratch.path("no/such/sensor"), 0, kDec7 * 2)).empty());
}

TEST_CASE("an interval that does not start at or after the end of the last is refused, counted and said once, after a reopen too") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  {
    auto record = LongRecord::open(dir);
    append(record, 0, 5);
    CHECK(record.append(interval(4)) == LongRecord::Appended::behind);
    IntervalRecord overlapping = interval(4);
    overlapping.start_unix_ms += 30'000;  // starts inside the last one
    CHECK(record.append(overlapping) == LongRecord::Appended::behind);
    CHECK(record.behind() == 2);
    const auto notices = record.take_notices();
    REQUIRE(notices.size() == 1);
    CHECK(notices[0].problem);
    CHECK(notices[0].text.find("2026-12-07T00:04:00.000Z is refused") != std::string::npos);
    append(record, 5, 6);
  }
  auto record = LongRecord::open(dir);
  CHECK(record.written_until() == kDec7 + 6 * kMinute);
  CHECK(record.append(interval(2)) == LongRecord::Appended::behind);
  append(record, 6, 7);
  CHECK(numbers(everything(dir)) == range(0, 7));
}

TEST_CASE("a record cut short by a crash is cut off when the record opens again, and appends go on after the last whole one") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  const fs::path file = dir / "2026-12-07.rec";
  {
    auto record = LongRecord::open(dir);
    append(record, 0, 10);
  }
  fs::resize_file(file, records_end(10) - 30);  // the last write torn 42 bytes in
  CHECK(numbers(everything(dir)) == range(0, 9));  // a reader leaves the torn tail out
  auto record = LongRecord::open(dir);
  REQUIRE(record.repairs().size() == 1);
  CHECK(record.repairs()[0] == "2026-12-07.rec: cut at byte 664: a record cut short");
  CHECK(fs::file_size(file) == records_end(9));
  CHECK(record.written_until() == kDec7 + 9 * kMinute);
  append(record, 9, 12);
  CHECK(numbers(everything(dir)) == range(0, 12));
}

TEST_CASE("a day file whose header a crash cut short gets its header again") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  fs::create_directories(dir);
  std::ofstream(dir / "2026-12-07.rec") << "tgre";
  auto record = LongRecord::open(dir);
  CHECK(everything(dir).empty());
  REQUIRE(record.repairs().size() == 1);
  CHECK(record.repairs()[0] == "2026-12-07.rec: a header cut short, written again");
  append(record, 0, 3);
  CHECK(numbers(everything(dir)) == range(0, 3));
}

TEST_CASE("a corrupt record in the middle of a file is skipped and counted, and the records around it read") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  auto record = LongRecord::open(dir);
  append(record, 0, 10);
  flip_byte(dir / "2026-12-07.rec", records_end(4) + 25);  // in record 4's x_min
  LongRecordReader reader(dir, 0, kDec7 * 2);
  std::vector<int> expected = range(0, 4);
  for (int i = 5; i < 10; ++i) expected.push_back(i);
  CHECK(numbers(read_all(std::move(reader))) == expected);
  LongRecordReader counting(dir, 0, kDec7 * 2);
  (void)counting.next(100);
  CHECK(counting.corrupt() == 1);
  CHECK(counting.problems().empty());
  append(record, 10, 11);  // the record goes on
  auto reopened = LongRecord::open(dir);
  CHECK(reopened.written_until() == kDec7 + 11 * kMinute);
}

TEST_CASE("a day file whose header is damaged is skipped by readers, moved aside when the record opens, and the record goes on") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  {
    auto record = LongRecord::open(dir);
    append(record, kDayMinutes - 3, kDayMinutes + 3);  // 3 on the 7th, 3 on the 8th
  }
  flip_byte(dir / "2026-12-08.rec", 2);
  LongRecordReader reader(dir, 0, kDec7 * 2);
  CHECK(numbers(read_all(std::move(reader))) == range(kDayMinutes - 3, kDayMinutes));
  LongRecordReader naming(dir, 0, kDec7 * 2);
  (void)naming.next(100);
  REQUIRE(naming.problems().size() == 1);
  CHECK(naming.problems()[0].find("2026-12-08.rec: not a long record file") != std::string::npos);

  auto record = LongRecord::open(dir);
  REQUIRE(record.repairs().size() == 1);
  CHECK(record.repairs()[0] ==
        "2026-12-08.rec: its header is not a long record's: moved to 2026-12-08.rec.damaged");
  // What the 7th holds is where the record ends now: the 8th's three are in the damaged file.
  CHECK(record.written_until() == kDec7 + kDayMinutes * kMinute);
  append(record, kDayMinutes + 5, kDayMinutes + 6);
  CHECK(file_names(dir) == std::vector<std::string>{"2026-12-07.rec", "2026-12-08.rec",
                                                    "2026-12-08.rec.damaged"});
  std::vector<int> expected = range(kDayMinutes - 3, kDayMinutes);
  expected.push_back(kDayMinutes + 5);
  CHECK(numbers(everything(dir)) == expected);
}

TEST_CASE("retention removes whole day files older than keep_days before the clock's day") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  auto record = LongRecord::open(dir, keeping(2));
  for (int day = 0; day < 5; ++day) append(record, day * kDayMinutes, day * kDayMinutes + 2);
  std::ofstream(dir / "2026-12-07.rec.damaged") << "left by an earlier repair";
  const std::int64_t noon_of_day_4 = kDec7 + 4 * kDayMs + kDayMs / 2;
  CHECK(record.remove_expired(noon_of_day_4) == 3);  // the 7th, its damaged copy, the 8th
  CHECK(file_names(dir) ==
        std::vector<std::string>{"2026-12-09.rec", "2026-12-10.rec", "2026-12-11.rec"});
  CHECK(record.remove_expired(noon_of_day_4) == 0);
  CHECK(record.removed_files() == 3);
  CHECK(everything(dir).front().start_unix_ms == kDec7 + 2 * kDayMs);
  // A day later, the 9th goes too; what is written on goes on.
  append(record, 5 * kDayMinutes, 5 * kDayMinutes + 1);
  CHECK(record.remove_expired(noon_of_day_4 + kDayMs) == 1);
  CHECK(everything(dir).size() == 5);
  CHECK(record.take_notices().empty());
}

TEST_CASE("retention keeps the keep_days before the newest interval whatever the clock says, and nothing for a clock behind") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  auto record = LongRecord::open(dir, keeping(2));
  for (int day = 0; day < 5; ++day) append(record, day * kDayMinutes, day * kDayMinutes + 2);
  CHECK(record.remove_expired(kDec7 - 100 * kDayMs) == 0);  // a clock far behind: nothing
  CHECK(record.remove_expired(kDec7 + 400 * kDayMs) == 2);  // far ahead: the 7th and 8th only
  CHECK(file_names(dir).size() == 3);
  // A reopened record knows where it ends before any append.
  auto reopened = LongRecord::open(dir, keeping(0));
  CHECK(reopened.remove_expired(kDec7 + 400 * kDayMs) == 2);
  CHECK(file_names(dir) == std::vector<std::string>{"2026-12-11.rec"});
}

TEST_CASE("the record after a SIGKILL holds every interval appended before it, whole and in order") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  int ready[2];
  REQUIRE(::pipe(ready) == 0);
  const pid_t child = ::fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    // The gateway's part: appending without a sync (a process crash needs none) until killed.
    ::close(ready[0]);
    LongRecordOptions options;
    options.sync_every = 0;
    auto record = LongRecord::open(dir, options);
    for (int i = 0;; ++i) {
      if (record.append(interval(i)) != LongRecord::Appended::written) ::_exit(1);
      if (i == 200) (void)!::write(ready[1], "r", 1);
    }
  }
  ::close(ready[1]);
  pollfd waiting{ready[0], POLLIN, 0};
  const bool started = ::poll(&waiting, 1, 10'000) == 1;
  ::usleep(2'000);  // killed in the middle of its appends
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ::close(ready[0]);
  REQUIRE(started);
  CHECK(WIFSIGNALED(status));

  auto record = LongRecord::open(dir);
  LongRecordReader reader(dir, 0, kDec7 * 2);
  const auto all = read_all(std::move(reader), 1000);
  REQUIRE(all.size() > 200);
  CHECK(numbers(all) == range(0, static_cast<int>(all.size())));
  CHECK(record.written_until() == all.back().end_unix_ms());
  const int next = static_cast<int>(all.size());
  append(record, next, next + 1);
  LongRecordReader after(dir, 0, kDec7 * 2);
  const auto again = read_all(std::move(after), 1000);
  CHECK(numbers(again) == range(0, next + 1));
}

TEST_CASE("a directory made where a day's file should be is cleared out of the way, and the record goes on") {
  ScratchDir scratch;
  const fs::path dir = record_dir(scratch);
  fs::create_directories(dir / "2026-12-07.rec");
  auto record = LongRecord::open(dir);
  CHECK_FALSE(record.disk_fault().has_value());
  REQUIRE(record.repairs().size() == 1);
  CHECK(record.repairs()[0] == "2026-12-07.rec: an empty directory in the file's place, removed");
  append(record, 0, 2);
  CHECK(numbers(everything(dir)) == range(0, 2));
}

TEST_CASE("each sensor's record has a folder of its own under record/, whatever its name") {
  CHECK(record_directory("/var/lib/tiltgate", "boom") == fs::path("/var/lib/tiltgate/record/boom"));
  CHECK(record_directory("/s", "mast-2.top") == fs::path("/s/record/mast-2.top"));
  CHECK(record_directory("/s", "..") == fs::path("/s/record/%2E."));  // not /s itself
  CHECK(record_directory("/s", ".") == fs::path("/s/record/%2E"));    // not record/
  CHECK(record_directory("/s", ".hidden") == fs::path("/s/record/%2Ehidden"));
}
