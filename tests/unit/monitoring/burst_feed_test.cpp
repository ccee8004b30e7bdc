// The bursts' samples for the feeds (monitoring/burst_feed.h): numbered in order, taken after
// a number, at most as many as asked, and bounded.
#include <doctest/doctest.h>

#include "monitoring/burst_feed.h"

using namespace tiltgate;
using namespace tiltgate::monitoring;

namespace {

BurstBatch batch(const char* phase, std::int64_t first_ms, int samples) {
  BurstBatch b{0, "mast", "2026-12-07T10-15-02.250Z", phase, {}};
  for (int i = 0; i < samples; ++i) {
    FedSample s;
    s.unix_ms = first_ms + i * 10;
    b.samples.push_back(s);
  }
  return b;
}

}  // namespace

TEST_CASE("burst feed: batches are numbered in order and taken after a number") {
  BurstFeed feed;
  CHECK(feed.last() == 0);
  feed.push(batch("pre", 1000, 3));
  feed.push(batch("trigger", 2000, 1));
  feed.push(batch("burst", 2010, 5));
  feed.push(batch("burst", 3000, 0));  // nothing to say: not kept, not numbered
  CHECK(feed.last() == 3);
  const auto all = feed.after(0, 10);
  REQUIRE(all.size() == 3);
  CHECK(all[0].seq == 1);
  CHECK(all[0].phase == "pre");
  CHECK(all[2].samples.size() == 5);
  const auto later = feed.after(1, 1);
  REQUIRE(later.size() == 1);
  CHECK(later[0].phase == "trigger");
  CHECK(feed.after(3, 10).empty());
}

TEST_CASE("burst feed: past its bound the oldest batches go") {
  BurstFeed feed;
  for (std::size_t i = 0; i < BurstFeed::kBatchesKept + 10; ++i) feed.push(batch("burst", 0, 1));
  const auto kept = feed.after(0, 1000);
  REQUIRE(kept.size() == BurstFeed::kBatchesKept);
  CHECK(kept.front().seq == 11);
  CHECK(kept.back().seq == BurstFeed::kBatchesKept + 10);
}
