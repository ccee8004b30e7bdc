// The audit trail (audit/audit_trail.h): what recent() finds and in what order, its bound,
// the records kept across a restart, what a torn last record costs, reading the folder
// beside the trail, and the counts /metrics shows; its writer thread: records on disk after a
// flush, everything queued written at shutdown, and records a full disk refused written once
// it takes them again.
#include <doctest/doctest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <spdlog/spdlog.h>
#include <optional>
#include <string>
#include <thread>

#include "audit/audit_json.h"
#include "audit/audit_text.h"
#include "audit/audit_trail.h"
#include "unit/support/small_disk.h"

using namespace tiltgate;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

struct StateDir {
  StateDir() {
    std::string pattern = (fs::temp_directory_path() / "tiltgate-audit-XXXXXX").string();
    REQUIRE(::mkdtemp(pattern.data()) != nullptr);
    path = pattern;
  }
  ~StateDir() { fs::remove_all(path); }
  std::string path;
};

AuditRecord change(std::int64_t ms, std::string door, std::string sensor, std::string setting,
                   std::string result = "ack") {
  return {ms, {std::move(door), "10.0.0.5:50122"}, std::move(sensor), std::move(setting), "2",
          "3", std::move(result)};
}

std::vector<std::int64_t> times(const std::vector<AuditRecord>& records) {
  std::vector<std::int64_t> out;
  for (const AuditRecord& r : records) out.push_back(r.unix_ms);
  return out;
}

// A filter with one field set (g++ warns of the fields a designated initializer leaves out).
template <class Set>
AuditTrail::Filter only(Set set) {
  AuditTrail::Filter filter;
  set(filter);
  return filter;
}

// The segment files of the trail's folder, oldest first.
std::vector<fs::path> segments(const std::string& state_dir) {
  std::vector<fs::path> found;
  for (const auto& entry : fs::directory_iterator(audit_folder(state_dir)))
    if (entry.path().extension() == ".seg") found.push_back(entry.path());
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace

TEST_CASE("the audit trail gives the newest records first, filtered by door, sensor, who, setting and time") {
  AuditTrail trail("");
  trail.record(change(1000, "modbus", "line1/a", "filter"));
  trail.record(change(2000, "sparkplug", "line1/b", "zero", "nak 0x03"));
  trail.record(change(3000, "modbus", "line1/b", "filter", "timeout"));
  CHECK(times(trail.recent({})) == std::vector<std::int64_t>{3000, 2000, 1000});
  CHECK(times(trail.recent(only([](AuditTrail::Filter& f) { f.door = "modbus"; }))) == std::vector<std::int64_t>{3000, 1000});
  CHECK(times(trail.recent(only([](AuditTrail::Filter& f) { f.sensor = "line1/b"; }))) == std::vector<std::int64_t>{3000, 2000});
  CHECK(times(trail.recent(only([](AuditTrail::Filter& f) { f.setting = "zero"; }))) == std::vector<std::int64_t>{2000});
  CHECK(times(trail.recent(only([](AuditTrail::Filter& f) { f.who = "10.0.0.5"; }))).size() == 3);
  CHECK(trail.recent(only([](AuditTrail::Filter& f) { f.who = "10.0.0.6"; })).empty());
  CHECK(times(trail.recent(only([](AuditTrail::Filter& f) { f.since_ms = 2000; }))) == std::vector<std::int64_t>{3000, 2000});
  CHECK(times(trail.recent(only([](AuditTrail::Filter& f) { f.limit = 2; }))) == std::vector<std::int64_t>{3000, 2000});
  CHECK(trail.folder().empty());  // no state_dir: in memory
}

TEST_CASE("a record without a time gets the wall clock's") {
  AuditTrail trail("");
  trail.record(change(0, "modbus", "line1/a", "filter"));
  CHECK(trail.recent({}).front().unix_ms > 1'700'000'000'000);
}

TEST_CASE("the audit trail keeps its newest max_records, the oldest dropped") {
  AuditTrail trail("", 3);
  for (int i = 1; i <= 5; ++i) trail.record(change(i, "modbus", "line1/a", "filter"));
  CHECK(times(trail.recent(only([](AuditTrail::Filter& f) { f.limit = 0; }))) == std::vector<std::int64_t>{5, 4, 3});
}

TEST_CASE("the audit trail counts records by door and result class since start") {
  AuditTrail trail("");
  trail.record(change(1, "modbus", "line1/a", "filter"));
  trail.record(change(2, "modbus", "line1/a", "filter", "nak 0x03"));
  trail.record(change(3, "modbus", "line1/a", "filter", "refused: out of range"));
  trail.record(change(4, "control socket", "line1/a", "address", "ack"));
  trail.record(change(5, "modbus", "line1/a", "filter", "timeout"));
  trail.record(change(6, "modbus", "line1/a", "filter", "nak"));
  const AuditCounts expected = {{"control socket", "ack", 1}, {"modbus", "ack", 1},
                                {"modbus", "nak", 2},         {"modbus", "refused", 1},
                                {"modbus", "timeout", 1}};
  CHECK(trail.counts() == expected);
  CHECK(audit_result_class("error: gateway stopping") == "error");
  CHECK(audit_result_class("ok") == "ok");
  CHECK(audit_result_class("acknowledged") == "error");  // not a class's word
}

TEST_CASE("the audit trail keeps its records across a restart, and what was recorded before it opened its folder") {
  StateDir dir;
  {
    AuditTrail trail("");
    trail.record(change(1000, "modbus", "line1/a", "filter"));  // before the user switch
    trail.open(dir.path);
    CHECK(trail.folder() == audit_folder(dir.path));
    trail.record(change(2000, "control socket", "line1/a", "address"));
  }
  AuditTrail reopened(dir.path);
  const auto records = reopened.recent({});
  REQUIRE(records.size() == 2);
  CHECK(records[0] == change(2000, "control socket", "line1/a", "address"));
  CHECK(records[1] == change(1000, "modbus", "line1/a", "filter"));
  CHECK(reopened.counts().empty());  // counted since start
  // Read without opening it: what `tiltgate audit` shows.
  const auto read = read_audit_folder(audit_folder(dir.path));
  REQUIRE(read.has_value());
  CHECK(times(*read) == std::vector<std::int64_t>{1000, 2000});
}

TEST_CASE("a torn last record of the audit trail loses only it") {
  StateDir dir;
  {
    AuditTrail trail(dir.path);
    for (int i = 1; i <= 3; ++i) trail.record(change(i * 1000, "modbus", "line1/a", "filter"));
  }
  const fs::path last = segments(dir.path).back();
  fs::resize_file(last, fs::file_size(last) - 5);  // a crash in the middle of the last write
  // Read beside a gateway, the torn record is not shown, and nothing is cut.
  const auto read = read_audit_folder(audit_folder(dir.path));
  REQUIRE(read.has_value());
  CHECK(times(*read) == std::vector<std::int64_t>{1000, 2000});
  {
    AuditTrail reopened(dir.path);
    CHECK(times(reopened.recent({})) == std::vector<std::int64_t>{2000, 1000});
    reopened.record(change(4000, "modbus", "line1/a", "zero"));
  }
  AuditTrail again(dir.path);
  CHECK(times(again.recent({})) == std::vector<std::int64_t>{4000, 2000, 1000});
}

TEST_CASE("an audit trail whose folder cannot be made is kept in memory") {
  StateDir dir;
  const std::string file = dir.path + "/a-file";
  { std::ofstream(file) << "x"; }
  AuditTrail trail(file);  // <file>/audit cannot be a folder
  CHECK(trail.folder().empty());
  trail.record(change(1, "modbus", "line1/a", "filter"));
  CHECK(trail.recent({}).size() == 1);
}

TEST_CASE("the audit trail's disk stays within its budget, the oldest records dropped") {
  StateDir dir;
  AuditTrail trail(dir.path, 100);
  // Each record is also logged: 6 MB of journal lines here.
  const auto level = spdlog::get_level();
  spdlog::set_level(spdlog::level::warn);
  const std::string big(20000, 'x');  // about 20 KB a record: the 4 MiB budget in ~210
  for (int i = 1; i <= 300; ++i) {
    AuditRecord r = change(i, "modbus", "line1/a", "filter");
    r.new_value = big;
    trail.record(std::move(r));
  }
  spdlog::set_level(level);
  REQUIRE(trail.flush());
  std::uintmax_t bytes = 0;
  for (const fs::path& segment : segments(dir.path)) bytes += fs::file_size(segment);
  CHECK(bytes <= kAuditStoreBytes);
  const auto read = read_audit_folder(audit_folder(dir.path));
  REQUIRE(read.has_value());
  CHECK(read->back().unix_ms == 300);
  CHECK(read->front().unix_ms > 1);  // the oldest went
  CHECK(trail.recent(only([](AuditTrail::Filter& f) { f.limit = 0; })).size() == 100);
}

TEST_CASE("an audit record goes to JSON and back, and reads as one line of text") {
  const AuditRecord record = change(1733380000123, "modbus", "line1/a", "filter", "nak 0x03");
  const auto back = audit_record_from_json(audit_record_json(record));
  REQUIRE(back.has_value());
  CHECK(*back == record);
  CHECK(audit_json({record}).front() == '[');
  CHECK(audit_text(record) == "door modbus, who 10.0.0.5:50122: line1/a filter 2 -> 3: nak 0x03");
  AuditRecord unknown_old = record;
  unknown_old.old_value.clear();
  CHECK(audit_text(unknown_old) == "door modbus, who 10.0.0.5:50122: line1/a filter = 3: nak 0x03");
  CHECK_FALSE(audit_record_from_json("not json").has_value());
}

TEST_CASE("a second audit trail on the same state_dir keeps its records in memory, the first's files untouched") {
  StateDir dir;
  AuditTrail first(dir.path);
  AuditTrail second(dir.path);
  CHECK(first.folder() == audit_folder(dir.path));
  CHECK(second.folder().empty());
  second.record(change(1, "modbus", "line1/a", "filter"));
  first.record(change(2, "modbus", "line1/a", "zero"));
  REQUIRE(first.flush());
  CHECK_FALSE(second.flush());  // in memory only
  const auto read = read_audit_folder(audit_folder(dir.path));
  REQUIRE(read.has_value());
  CHECK(times(*read) == std::vector<std::int64_t>{2});
}

TEST_CASE("a record is seen at once and is on disk after a flush") {
  StateDir dir;
  AuditTrail trail(dir.path);
  for (int i = 1; i <= 3; ++i) trail.record(change(i * 1000, "modbus", "line1/a", "filter"));
  CHECK(times(trail.recent({})) == std::vector<std::int64_t>{3000, 2000, 1000});
  CHECK(trail.counts() == AuditCounts{AuditCount{"modbus", "ack", 3}});
  REQUIRE(trail.flush());
  const auto read = read_audit_folder(audit_folder(dir.path));
  REQUIRE(read.has_value());
  CHECK(times(*read) == std::vector<std::int64_t>{1000, 2000, 3000});
}

TEST_CASE("at shutdown the audit trail writes everything queued, and a record after close() too") {
  StateDir dir;
  const auto level = spdlog::get_level();
  spdlog::set_level(spdlog::level::warn);
  {
    AuditTrail trail(dir.path);
    for (int i = 1; i <= 500; ++i) trail.record(change(i, "modbus", "line1/a", "filter"));
  }  // no flush: the destructor's close()
  AuditTrail closed(dir.path);
  closed.close();
  closed.record(change(501, "modbus", "line1/a", "filter"));
  spdlog::set_level(level);
  const auto read = read_audit_folder(audit_folder(dir.path));
  REQUIRE(read.has_value());
  REQUIRE(read->size() == 501);
  for (std::size_t i = 0; i < read->size(); ++i) CHECK((*read)[i].unix_ms == std::int64_t(i + 1));
}

TEST_CASE("records a full disk refuses stay in memory and the writer writes them once it has room") {
  test::SmallDisk disk;
  if (test::no_small_disk(disk)) return;
  const std::string state_dir = disk.path("state").string();
  AuditTrail trail(state_dir);
  trail.record(change(1, "modbus", "line1/a", "filter"));
  REQUIRE(trail.flush());
  const auto level = spdlog::get_level();
  spdlog::set_level(spdlog::level::critical);  // the store's notices, and 60 journal lines
  disk.fill();
  // More than the segment's last page holds: some must wait for room.
  for (int i = 2; i <= 61; ++i) trail.record(change(i, "modbus", "line1/a", "filter"));
  CHECK_FALSE(trail.flush());
  CHECK(trail.recent(only([](AuditTrail::Filter& f) { f.limit = 0; })).size() == 61);
  disk.free();
  // The writer's own next try, without a flush.
  std::optional<std::vector<AuditRecord>> read;
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  do {
    std::this_thread::sleep_for(50ms);
    auto found = read_audit_folder(audit_folder(state_dir));
    if (found) read = std::move(*found);
  } while ((!read || read->size() < 61) && std::chrono::steady_clock::now() < deadline);
  spdlog::set_level(level);
  REQUIRE(read.has_value());
  REQUIRE(read->size() == 61);
  for (std::size_t i = 0; i < read->size(); ++i) CHECK((*read)[i].unix_ms == std::int64_t(i + 1));
  CHECK(trail.flush());
}
