// The DDATA the edge node could not publish (the broker away, the primary host offline), kept
// in the on-disk store (store/record_store.h) and replayed once the births are out again
// (docs/northbound.md, "The store"): oldest first, at most `per_step` records a step, so the
// replay never holds up the live data the same tick publishes first.
//
// Threads: the gateway's event loop only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "driver/expected.h"
#include "sparkplug/edge_node_session.h"
#include "store/record_store.h"

namespace tiltgate::sparkplug {

struct BacklogCounts {
  std::uint64_t bytes = 0;
  std::uint64_t records = 0;   // kept, not yet replayed
  std::uint64_t dropped = 0;   // dropped for the budget, oldest first, or too large: since the start
  std::uint64_t replayed = 0;  // published again since the start
  std::uint64_t skipped = 0;   // not replayable: their device is offline or gone now
  std::uint64_t lost = 0;      // lost to a damaged file
};

class DdataBacklog {
 public:
  // Opens (or creates) the store in `dir`, of `budget_bytes` at most.
  static Expected<DdataBacklog, std::string> open(const std::filesystem::path& dir,
                                                  std::uint64_t budget_bytes);

  // Appends a kept DDATA (in memory while the disk refuses it); an error (a DDATA larger than
  // a segment) loses that record only, counted as dropped.
  Expected<Done, std::string> keep(const Keep& keep);
  // Up to `per_step` kept records, oldest first, made publishable by `session` and handed to
  // `publish` (false: not sent, the replay stops there and goes on later). A record whose
  // device is offline or no longer configured is skipped (counted); the replay stops while the
  // session is not live.
  Expected<std::size_t, std::string> replay(EdgeNodeSession& session, Instant now,
                                            std::size_t per_step,
                                            const std::function<bool(const Publish&)>& publish);
  Expected<Done, std::string> sync() { return store_.sync(); }
  std::vector<store::StoreNotice> take_notices() { return store_.take_notices(); }

  BacklogCounts counts() const;
  const store::RecordStore& store() const { return store_; }

 private:
  explicit DdataBacklog(store::RecordStore store) : store_(std::move(store)) {}

  store::RecordStore store_;
  std::uint64_t skipped_ = 0;
  std::uint64_t refused_ = 0;  // too large to keep
};

}  // namespace tiltgate::sparkplug
