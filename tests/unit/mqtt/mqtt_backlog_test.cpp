// The JSON feed's backlog (mqtt/mqtt_backlog.h), in memory and on disk alike: oldest first, the
// oldest dropped and counted past `backlog` messages or buffer_mb bytes, replayed ones popped
// and counted; and on disk only (mqtt/stored_backlog.h): kept across a restart, a torn last
// record costs only that record, a second gateway on the same directory is refused.
#include <doctest/doctest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "mqtt/memory_backlog.h"
#include "mqtt/stored_backlog.h"
#include "unit/support/scratch_dir.h"
#include "unit/support/small_disk.h"

using namespace tiltgate;
using namespace tiltgate::test;
namespace fs = std::filesystem;

namespace {

// State i: 10 + 57 = 67 bytes in memory, 8 + 12 + 67 = 87 on disk.
MqttMessage state(int i) {
  char payload[80];
  std::snprintf(payload, sizeof payload, "{\"ts\":%013d,\"x\":1.5,\"historical\":true,\"n\":%06d}", i, i);
  return {"gw/s/state", payload, false, 1796176370000 + i};
}
constexpr std::uint64_t kStoredBytes = 87;

std::vector<int> numbers(const std::vector<MqttMessage>& messages) {
  std::vector<int> out;
  for (const MqttMessage& m : messages) out.push_back(std::stoi(m.payload.substr(6, 13)));
  return out;
}

void append(MqttBacklog& backlog, int from, int to) {
  for (int i = from; i < to; ++i) REQUIRE(backlog.append(state(i)).has_value());
}

std::vector<int> peek_all(MqttBacklog& backlog) {
  auto messages = backlog.peek(100000);
  REQUIRE(messages.has_value());
  return numbers(*messages);
}

std::vector<int> range(int from, int to) {
  std::vector<int> out;
  for (int i = from; i < to; ++i) out.push_back(i);
  return out;
}

std::unique_ptr<StoredBacklog> stored(const ScratchDir& dir, BacklogLimits limits) {
  auto backlog = StoredBacklog::open(dir.path("mqtt"), limits, 1);
  REQUIRE(backlog.has_value());
  return std::make_unique<StoredBacklog>(std::move(*backlog));
}

// Both kinds, for the cases that hold for both.
struct Kinds {
  ScratchDir dir{"tiltgate-backlog"};
  std::unique_ptr<MqttBacklog> make(const std::string& kind, BacklogLimits limits) {
    if (kind == "memory") return std::make_unique<MemoryBacklog>(limits);
    return stored(dir, limits);
  }
};

}  // namespace

TEST_CASE("mqtt backlog: messages come back oldest first, popped ones are gone and counted") {
  for (const std::string kind : {"memory", "disk"}) {
    INFO(kind);
    Kinds kinds;
    auto backlog = kinds.make(kind, {1024 * 1024, std::nullopt});
    append(*backlog, 0, 10);
    auto first = backlog->peek(4);
    REQUIRE(first.has_value());
    CHECK(numbers(*first) == range(0, 4));
    CHECK((*first)[0] == state(0));
    CHECK(peek_all(*backlog) == range(0, 10));  // peek alone takes nothing
    REQUIRE(backlog->pop(4).has_value());
    CHECK(peek_all(*backlog) == range(4, 10));
    CHECK(backlog->stats().records == 6);
    CHECK(backlog->stats().replayed == 4);
    CHECK(backlog->stats().dropped == 0);
    CHECK(backlog->stats().bytes > 0);
  }
}

TEST_CASE("mqtt backlog: past `backlog` messages the oldest are dropped and counted") {
  for (const std::string kind : {"memory", "disk"}) {
    INFO(kind);
    Kinds kinds;
    auto backlog = kinds.make(kind, {1024 * 1024, std::size_t{10}});
    append(*backlog, 0, 25);
    const StoreStats stats = backlog->stats();
    CHECK(stats.records <= 10);
    CHECK(stats.records >= 9);  // on disk it drops to 90 % at once
    CHECK(stats.dropped == 25 - stats.records);
    CHECK(stats.replayed == 0);
    const std::vector<int> kept = peek_all(*backlog);
    CHECK(kept == range(25 - int(kept.size()), 25));  // the newest
  }
}

TEST_CASE("mqtt backlog: backlog = 0 keeps nothing and counts every message") {
  for (const std::string kind : {"memory", "disk"}) {
    INFO(kind);
    Kinds kinds;
    auto backlog = kinds.make(kind, {1024 * 1024, std::size_t{0}});
    append(*backlog, 0, 3);
    CHECK(backlog->empty());
    CHECK(backlog->stats().dropped == 3);
  }
}

TEST_CASE("mqtt backlog: past buffer_mb bytes the oldest are dropped and counted") {
  for (const std::string kind : {"memory", "disk"}) {
    INFO(kind);
    Kinds kinds;
    // On disk: segments of 1000 bytes (8 + 11 states), two of them at most.
    auto backlog = kinds.make(kind, {2000, std::nullopt});
    append(*backlog, 0, 100);
    const StoreStats stats = backlog->stats();
    CHECK(stats.bytes <= 2000);
    CHECK(stats.records + stats.dropped == 100);
    CHECK(stats.dropped >= 60);
    const std::vector<int> kept = peek_all(*backlog);
    CHECK(kept == range(100 - int(kept.size()), 100));
  }
}

TEST_CASE("mqtt backlog on disk: a restart keeps what was not replayed, and where the replay was") {
  ScratchDir dir("tiltgate-backlog");
  {
    auto backlog = stored(dir, {1024 * 1024, std::nullopt});
    append(*backlog, 0, 20);
    REQUIRE(backlog->pop(5).has_value());
  }  // the gateway stops
  auto reopened = stored(dir, {1024 * 1024, std::nullopt});
  CHECK(peek_all(*reopened) == range(5, 20));
  append(*reopened, 20, 22);
  CHECK(peek_all(*reopened) == range(5, 22));
  CHECK(reopened->stats().replayed == 0);  // counted since this start
}

TEST_CASE("mqtt backlog on disk: a smaller `backlog` after a restart applies to what is kept") {
  ScratchDir dir("tiltgate-backlog");
  { append(*stored(dir, {1024 * 1024, std::nullopt}), 0, 50); }
  auto reopened = stored(dir, {1024 * 1024, std::size_t{20}});
  CHECK(reopened->stats().records <= 20);
  CHECK(reopened->stats().dropped == 50 - reopened->stats().records);
  CHECK(peek_all(*reopened).back() == 49);
}

TEST_CASE("mqtt backlog on disk: a write torn by a power cut loses at most the last message") {
  ScratchDir dir("tiltgate-backlog");
  { append(*stored(dir, {1024 * 1024, std::nullopt}), 0, 10); }
  fs::path segment;
  for (const auto& entry : fs::directory_iterator(dir.path("mqtt")))
    if (entry.path().extension() == ".seg") segment = entry.path();
  REQUIRE(!segment.empty());
  const std::uint64_t size = fs::file_size(segment);
  fs::resize_file(segment, size - kStoredBytes / 2);  // the last record cut in its middle
  auto reopened = stored(dir, {1024 * 1024, std::nullopt});
  CHECK(peek_all(*reopened) == range(0, 9));
  CHECK(reopened->repairs().size() == 1);
  append(*reopened, 10, 12);  // and it goes on after the cut
  CHECK(peek_all(*reopened).back() == 11);
}

TEST_CASE("mqtt backlog on disk: a second gateway on the same state_dir is refused") {
  ScratchDir dir("tiltgate-backlog");
  auto first = stored(dir, {1024 * 1024, std::nullopt});
  auto second = StoredBacklog::open(dir.path("mqtt"), {1024 * 1024, std::nullopt}, 1);
  REQUIRE_FALSE(second.has_value());
  CHECK(second.error().find("in use by another tiltgate") != std::string::npos);
  first.reset();  // closed: the lock goes with it
  CHECK(StoredBacklog::open(dir.path("mqtt"), {1024 * 1024, std::nullopt}, 1).has_value());
}

TEST_CASE("mqtt backlog on disk: a directory that cannot be made is an error, not a crash") {
  ScratchDir dir("tiltgate-backlog");
  const std::string file = dir.write("a-file", "x");
  auto backlog = StoredBacklog::open(fs::path(file) / "mqtt", {1024 * 1024, std::nullopt}, 1);
  REQUIRE_FALSE(backlog.has_value());
  CHECK(backlog.error().find("cannot create") != std::string::npos);
}

TEST_CASE("mqtt backlog on disk: a directory where the lock file should be is removed, and what was kept is replayed") {
  ScratchDir dir("tiltgate-backlog");
  { append(*stored(dir, {1024 * 1024, std::nullopt}), 0, 10); }
  fs::remove(dir.path("mqtt/lock"));
  fs::create_directory(dir.path("mqtt/lock"));
  auto reopened = stored(dir, {1024 * 1024, std::nullopt});
  CHECK(peek_all(*reopened) == range(0, 10));
  REQUIRE(reopened->repairs().size() == 1);
  CHECK(reopened->repairs()[0] == "lock: an empty directory in the file's place, removed");
}

TEST_CASE("mqtt backlog on disk: on a full disk the newest are kept in memory and the oldest dropped, each counted") {
  SmallDisk disk;
  if (no_small_disk(disk)) return;
  auto opened = StoredBacklog::open(disk.path("mqtt"), {16 * kStoredBytes, std::nullopt}, 1);
  REQUIRE(opened.has_value());
  StoredBacklog& backlog = *opened;
  append(backlog, 0, 4);
  disk.fill();
  append(backlog, 4, 60);
  const StoreStats stats = backlog.stats();
  CHECK(stats.records + stats.dropped == 60);
  const std::vector<int> kept = peek_all(backlog);
  REQUIRE(kept.size() == stats.records);
  CHECK(kept == range(60 - static_cast<int>(kept.size()), 60));
  const auto notices = backlog.take_notices();
  REQUIRE(notices.size() == 1);  // the disk's refusal, said once
  CHECK(notices[0].problem);
  disk.free();
  REQUIRE(backlog.sync().has_value());  // room again: written out
  CHECK(backlog.take_notices().size() == 1);
  CHECK(peek_all(backlog) == kept);
}
