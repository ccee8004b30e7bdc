// The audit trail's writer (audit/audit_writer.h) against a sink of the test's own, a disk
// that can be held busy or made to refuse: what queues up while the writer is busy goes out as
// one batch (one sync, not one per record), a refused batch is kept and tried again with what
// came meanwhile, and close() leaves nothing queued behind.
#include <doctest/doctest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>
#include <vector>

#include "audit/audit_writer.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

AuditRecord numbered(std::int64_t n) {
  return {n, {"modbus", "10.0.0.5:50122"}, "line1/a", "filter", "", "2", "ack"};
}

std::vector<std::int64_t> times(const std::vector<AuditRecord>& records) {
  std::vector<std::int64_t> out;
  for (const AuditRecord& r : records) out.push_back(r.unix_ms);
  return out;
}

std::vector<std::int64_t> range(std::int64_t from, std::int64_t to) {
  std::vector<std::int64_t> out;
  for (std::int64_t n = from; n < to; ++n) out.push_back(n);
  return out;
}

// A disk as the trail's sink sees one: what it takes is "synced" at once, what it refuses it
// holds, in order, until a later call finds it taking writes again. Each call can be held
// until the test lets it go, to keep the writer busy while records queue up.
class FakeDisk {
 public:
  AuditWriter::Sink sink() {
    return [this](const std::vector<AuditRecord>& batch) { return write(batch); };
  }

  void hold() {
    const std::lock_guard lock(mutex_);
    held_ = true;
  }
  void let_go() {
    {
      const std::lock_guard lock(mutex_);
      held_ = false;
    }
    changed_.notify_all();
  }
  // Waits until a call is held inside the sink.
  void wait_inside() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [this] { return inside_; });
  }
  void refuse(bool refusing) {
    const std::lock_guard lock(mutex_);
    refusing_ = refusing;
  }
  // Waits up to `patience` for `n` records on disk.
  bool wait_on_disk(std::size_t n, std::chrono::milliseconds patience) {
    std::unique_lock lock(mutex_);
    return changed_.wait_for(lock, patience, [&] { return on_disk_.size() >= n; });
  }

  std::vector<AuditRecord> on_disk() const {
    const std::lock_guard lock(mutex_);
    return on_disk_;
  }
  std::vector<std::size_t> batch_sizes() const {
    const std::lock_guard lock(mutex_);
    return batch_sizes_;
  }

 private:
  bool write(const std::vector<AuditRecord>& batch) {
    std::unique_lock lock(mutex_);
    batch_sizes_.push_back(batch.size());
    inside_ = true;
    changed_.notify_all();
    changed_.wait(lock, [this] { return !held_; });
    inside_ = false;
    pending_.insert(pending_.end(), batch.begin(), batch.end());
    if (!refusing_) {
      on_disk_.insert(on_disk_.end(), pending_.begin(), pending_.end());
      pending_.clear();
    }
    changed_.notify_all();
    return !refusing_;
  }

  mutable std::mutex mutex_;
  std::condition_variable changed_;
  bool held_ = false;
  bool inside_ = false;
  bool refusing_ = false;
  std::vector<AuditRecord> pending_;  // refused, held
  std::vector<AuditRecord> on_disk_;
  std::vector<std::size_t> batch_sizes_;
};

}  // namespace

TEST_CASE("the audit writer takes what queued up while it was busy as one batch: one sync, not one per record") {
  FakeDisk disk;
  AuditWriter writer(disk.sink());
  disk.hold();
  writer.push(numbered(1));
  disk.wait_inside();  // the writer is syncing record 1
  for (int n = 2; n <= 10; ++n) writer.push(numbered(n));
  disk.let_go();
  CHECK(writer.flush());
  CHECK(disk.batch_sizes() == std::vector<std::size_t>{1, 9});
  CHECK(writer.batches() == 2);
  CHECK(times(disk.on_disk()) == range(1, 11));
}

TEST_CASE("push() returns while the writer waits for the disk") {
  FakeDisk disk;
  AuditWriter writer(disk.sink());
  disk.hold();
  writer.push(numbered(1));
  disk.wait_inside();
  const auto start = std::chrono::steady_clock::now();
  for (int n = 2; n <= 100; ++n) writer.push(numbered(n));
  CHECK(std::chrono::steady_clock::now() - start < 1s);  // the disk is still held
  CHECK(disk.on_disk().empty());
  disk.let_go();
  CHECK(writer.flush());
  CHECK(times(disk.on_disk()) == range(1, 101));
}

TEST_CASE("records the disk refuses are kept and tried again, with those that came meanwhile, until it takes them") {
  FakeDisk disk;
  AuditWriter writer(disk.sink(), 20ms);
  disk.refuse(true);
  writer.push(numbered(1));
  writer.push(numbered(2));
  CHECK_FALSE(writer.flush());  // refused: held, nothing dropped
  writer.push(numbered(3));
  std::this_thread::sleep_for(100ms);  // a few tries, all refused
  CHECK(disk.on_disk().empty());
  const std::size_t tries = disk.batch_sizes().size();
  CHECK(tries >= 3);
  CHECK(tries < 20);  // at the retry's pace, not in a loop
  disk.refuse(false);
  // The writer's own next try, without a flush.
  REQUIRE(disk.wait_on_disk(3, 5s));
  CHECK(times(disk.on_disk()) == range(1, 4));
  CHECK(writer.flush());
}

TEST_CASE("close() writes everything queued before the writer ends, and a record after it is written at once") {
  FakeDisk disk;
  {
    AuditWriter writer(disk.sink());
    disk.hold();
    writer.push(numbered(1));
    disk.wait_inside();
    for (int n = 2; n <= 50; ++n) writer.push(numbered(n));
    std::thread closing([&] { writer.close(); });
    std::this_thread::sleep_for(20ms);
    disk.let_go();
    closing.join();
    CHECK(times(disk.on_disk()) == range(1, 51));
    writer.push(numbered(51));  // at shutdown, after close: by the caller
    CHECK(times(disk.on_disk()) == range(1, 52));
    CHECK(writer.flush());
  }
  // And the destructor closes: nothing pushed is left behind.
  FakeDisk other;
  {
    AuditWriter writer(other.sink());
    for (int n = 1; n <= 200; ++n) writer.push(numbered(n));
  }
  CHECK(times(other.on_disk()) == range(1, 201));
}
