// The DDATA kept on disk while the broker is away (sparkplug/ddata_backlog.h), with a real
// store in a scratch directory and a real session: kept in order, replayed after the births
// at most `per_step` a step, as historical DDATA with the readings' times; what cannot be
// replayed now; and the store across a reopen (a gateway restart).
#include <doctest/doctest.h>

#include "sparkplug/ddata_backlog.h"
#include "unit/sparkplug/sparkplug_session_support.h"
#include "unit/support/scratch_dir.h"
#include "unit/support/small_disk.h"

using namespace tiltgate;
using namespace tiltgate::sparkplug;
using namespace tiltgate::sparkplug::test;
using tiltgate::test::ScratchDir;
using tiltgate::test::SmallDisk;
using tiltgate::test::no_small_disk;

namespace {

constexpr std::uint64_t kBudget = 1 << 20;

// `count` readings of boom during an outage, one a second, each moved by 1 degree: each one
// is due and kept.
std::size_t keep_outage(EdgeNodeSession& session, DdataBacklog& backlog, int count) {
  std::size_t kept = 0;
  for (int i = 1; i <= count; ++i) {
    const DeviceSample samples[] = {boom(1.0 + i, 0.0, i * 1000), mast(3.0, i * 1000)};
    for (const Keep& k : all_of<Keep>(session.update(samples, at(i * 1000)))) {
      REQUIRE(backlog.keep(k).has_value());
      ++kept;
    }
  }
  return kept;
}

void reconnect(EdgeNodeSession& session, std::int64_t ms) {
  (void)session.begin_connect(at(ms));
  (void)session.on_connected(at(ms));
}

struct Sent {
  std::vector<Publish> messages;
  bool accept = true;
  std::function<bool(const Publish&)> sink() {
    return [this](const Publish& p) {
      if (!accept) return false;
      messages.push_back(p);
      return true;
    };
  }
};

}  // namespace

TEST_CASE("backlog: kept during the outage, nothing replayed before the births") {
  ScratchDir dir;
  auto backlog = DdataBacklog::open(dir.path("store"), kBudget);
  REQUIRE(backlog.has_value());
  LiveSession live;
  live.session.on_connection_lost();
  REQUIRE(keep_outage(live.session, *backlog, 5) == 5);
  CHECK(backlog->counts().records == 5);
  Sent sent;
  auto replayed = backlog->replay(live.session, at(6000), 50, sent.sink());
  REQUIRE(replayed.has_value());
  CHECK(*replayed == 0);
  CHECK(sent.messages.empty());
  CHECK(backlog->counts().records == 5);
}

TEST_CASE("backlog: replayed after the births, oldest first, at most per_step a step, "
          "historical with the readings' times and the next seq") {
  ScratchDir dir;
  auto backlog = DdataBacklog::open(dir.path("store"), kBudget);
  REQUIRE(backlog.has_value());
  LiveSession live;
  live.session.on_connection_lost();
  REQUIRE(keep_outage(live.session, *backlog, 7) == 7);
  reconnect(live.session, 8000);  // NBIRTH seq 0, DBIRTH boom 1, DBIRTH mast 2
  Sent sent;
  std::vector<std::size_t> per_step;
  for (int step = 0; step < 4; ++step) {
    auto replayed = backlog->replay(live.session, at(8000 + 100 * step), 3, sent.sink());
    REQUIRE(replayed.has_value());
    per_step.push_back(*replayed);
  }
  CHECK(per_step == std::vector<std::size_t>{3, 3, 1, 0});
  REQUIRE(sent.messages.size() == 7);
  for (std::size_t i = 0; i < sent.messages.size(); ++i) {
    CAPTURE(i);
    const Publish& p = sent.messages[i];
    CHECK(p.topic == "spBv1.0/plant/DDATA/gw1/boom");
    CHECK(p.payload.seq == 3 + i);
    const Metric* angle = find_alias(p.payload, device_alias(0, 1));
    REQUIRE(angle != nullptr);
    CHECK(angle->is_historical);
    CHECK(angle->timestamp == std::uint64_t(kUnixStart + 1000 * std::int64_t(i + 1)));
    CHECK(angle->value == Value{2.0 + double(i)});
  }
  const BacklogCounts counts = backlog->counts();
  CHECK(counts.records == 0);
  CHECK(counts.replayed == 7);
  CHECK(counts.skipped == 0);
}

TEST_CASE("backlog: a publish that fails stops the step and keeps the rest for later") {
  ScratchDir dir;
  auto backlog = DdataBacklog::open(dir.path("store"), kBudget);
  REQUIRE(backlog.has_value());
  LiveSession live;
  live.session.on_connection_lost();
  REQUIRE(keep_outage(live.session, *backlog, 4) == 4);
  reconnect(live.session, 5000);
  Sent sent;
  REQUIRE(backlog->replay(live.session, at(5000), 2, sent.sink()).value() == 2);
  sent.accept = false;
  REQUIRE(backlog->replay(live.session, at(5100), 2, sent.sink()).value() == 0);
  CHECK(backlog->counts().records == 2);
  sent.accept = true;
  REQUIRE(backlog->replay(live.session, at(5200), 2, sent.sink()).value() == 2);
  REQUIRE(sent.messages.size() == 4);
  CHECK(find_alias(sent.messages[2].payload, device_alias(0, 1))->value == Value{4.0});
}

TEST_CASE("backlog: a device offline at the replay is skipped and counted, the others go on") {
  ScratchDir dir;
  auto backlog = DdataBacklog::open(dir.path("store"), kBudget);
  REQUIRE(backlog.has_value());
  LiveSession live;
  live.session.on_connection_lost();
  REQUIRE(keep_outage(live.session, *backlog, 3) == 3);
  // boom is offline when the broker is back: no DBIRTH, so its kept data has no aliases.
  const DeviceSample samples[] = {offline(boom(4.0, 0.0, 4000)), mast(3.0, 4000)};
  (void)live.session.update(samples, at(4000));
  reconnect(live.session, 4000);
  Sent sent;
  REQUIRE(backlog->replay(live.session, at(4100), 50, sent.sink()).value() == 0);
  CHECK(sent.messages.empty());
  const BacklogCounts counts = backlog->counts();
  CHECK(counts.records == 0);
  CHECK(counts.skipped == 3);
  CHECK(counts.replayed == 0);
}

TEST_CASE("backlog: what was kept and not replayed survives a reopen, what was replayed does not "
          "come again") {
  ScratchDir dir;
  LiveSession live;
  live.session.on_connection_lost();
  {
    auto backlog = DdataBacklog::open(dir.path("store"), kBudget);
    REQUIRE(backlog.has_value());
    REQUIRE(keep_outage(live.session, *backlog, 5) == 5);
    reconnect(live.session, 6000);
    Sent sent;
    REQUIRE(backlog->replay(live.session, at(6000), 2, sent.sink()).value() == 2);
  }  // the gateway stops here, mid-replay
  auto reopened = DdataBacklog::open(dir.path("store"), kBudget);
  REQUIRE(reopened.has_value());
  CHECK(reopened->counts().records == 3);
  Sent sent;
  REQUIRE(reopened->replay(live.session, at(7000), 50, sent.sink()).value() == 3);
  REQUIRE(sent.messages.size() == 3);
  CHECK(find_alias(sent.messages[0].payload, device_alias(0, 1))->timestamp ==
        std::uint64_t(kUnixStart + 3000));
}

TEST_CASE("backlog: on a full disk the DDATA are kept in memory, the oldest dropped when full, and every one not kept is counted") {
  SmallDisk disk;
  if (no_small_disk(disk)) return;
  auto backlog = DdataBacklog::open(disk.path("store"), 8192);
  REQUIRE(backlog.has_value());
  LiveSession live;
  live.session.on_connection_lost();
  disk.fill();
  std::uint64_t kept = 0;
  for (int i = 1; i <= 400; ++i) {
    const DeviceSample samples[] = {boom(1.0 + i, 0.0, i * 1000), mast(3.0, i * 1000)};
    for (const Keep& k : all_of<Keep>(live.session.update(samples, at(i * 1000)))) {
      CHECK(backlog->keep(k).has_value());
      ++kept;
    }
  }
  const BacklogCounts counts = backlog->counts();
  CHECK(counts.dropped > 0);
  CHECK(counts.records + counts.dropped == kept);
  CHECK(backlog->take_notices().size() == 1);  // the disk's refusal, said once
}
