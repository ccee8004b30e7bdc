// The audit trail on a disk that refuses (docs/operations.md, "A disk that refuses the trail"),
// on a real full tmpfs: past the memory budget a record is lost, counted and said in the trail
// once the disk takes it again, the chain holding over it; [audit] when_full = "refuse" says
// no change may be made while the disk refuses, and yes again once it takes the trail.
#include <doctest/doctest.h>

#include <chrono>
#include <spdlog/spdlog.h>
#include <string>
#include <thread>

#include "audit/audit_trail.h"
#include "unit/support/small_disk.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

AuditRecord change(std::int64_t ms) {
  return {ms, {"modbus", "10.0.0.5:50122"}, "line1/a", "filter", "2", std::to_string(ms), "ack"};
}

// Until `done`, or 10 s: the writer tries again each second by itself.
template <class Done>
bool wait_for(Done done) {
  const auto deadline = std::chrono::steady_clock::now() + 10s;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(50ms);
  }
  return true;
}

struct QuietLog {
  QuietLog() : level(spdlog::get_level()) { spdlog::set_level(spdlog::level::critical); }
  ~QuietLog() { spdlog::set_level(level); }
  spdlog::level::level_enum level;
};

}  // namespace

TEST_CASE("past the memory budget a refused audit record is lost, counted, and said in the trail once the disk takes it again") {
  test::SmallDisk disk;
  if (test::no_small_disk(disk)) return;
  const std::string state_dir = disk.path("state").string();
  AuditTrail trail("");
  trail.open(state_dir, {.memory_budget_bytes = 2000, .when_full = AuditWhenFull::keep, .journal = {}});
  trail.record(change(1));
  REQUIRE(trail.flush());
  const QuietLog quiet;
  disk.fill();
  for (int i = 2; i <= 41; ++i) trail.record(change(i));
  CHECK_FALSE(trail.flush());
  const AuditHealth full = trail.health();
  CHECK(full.disk_refuses);
  CHECK(full.held > 0);
  CHECK(full.lost > 0);
  CHECK(trail.accepts_changes());  // when_full keep: changes go on
  disk.free();
  REQUIRE(wait_for([&] { return !trail.health().disk_refuses; }));
  CHECK(trail.health().held == 0);
  CHECK(trail.health().lost == full.lost);  // since start
  const auto read = read_audit_folder(audit_folder(state_dir));
  REQUIRE(read.has_value());
  // Every record but the lost ones, in order, then the one that says what was lost.
  REQUIRE(read->size() == 41 - full.lost + 1);
  const AuditRecord& notice = read->back();
  CHECK(notice.origin.door == "gateway");
  CHECK(notice.setting == "records lost");
  CHECK(notice.new_value == std::to_string(full.lost));
  CHECK(notice.result.starts_with("error: " + std::to_string(full.lost) + " records from"));
  CHECK(trail.recent({}).front().setting == "records lost");
  const auto check = verify_audit_folder(audit_folder(state_dir));
  REQUIRE(check.has_value());
  CHECK_FALSE(check->broken_at.has_value());
}

TEST_CASE("with when_full refuse the trail accepts no change while its disk refuses, and does again once it takes the trail") {
  test::SmallDisk disk;
  if (test::no_small_disk(disk)) return;
  const std::string state_dir = disk.path("state").string();
  AuditTrail trail("");
  trail.open(state_dir, {.memory_budget_bytes = 64 * 1024, .when_full = AuditWhenFull::refuse, .journal = {}});
  trail.record(change(1));
  REQUIRE(trail.flush());
  CHECK(trail.accepts_changes());
  const QuietLog quiet;
  disk.fill();
  for (int i = 2; i <= 41; ++i) trail.record(change(i));
  CHECK_FALSE(trail.flush());
  CHECK_FALSE(trail.accepts_changes());
  CHECK(trail.health().lost == 0);
  disk.free();
  REQUIRE(wait_for([&] { return trail.accepts_changes(); }));
  CHECK(read_audit_folder(audit_folder(state_dir))->size() == 41);
}
