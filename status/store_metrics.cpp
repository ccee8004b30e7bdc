#include "status/store_metrics.h"

namespace tiltgate {

namespace {

struct StoreFamily {
  const char* name;
  const char* type;
  const char* help;
  std::uint64_t StoreStats::*value;
};

const StoreFamily kStoreFamilies[] = {
    {"tiltgate_store_bytes", "gauge",
     "Bytes the feed's store of messages kept for the broker takes on disk (in memory without "
     "a state directory)",
     &StoreStats::bytes},
    {"tiltgate_store_records", "gauge", "Messages in the feed's store not yet replayed",
     &StoreStats::records},
    {"tiltgate_store_dropped_total", "counter",
     "Messages dropped from the feed's store, the oldest first, to stay within its size",
     &StoreStats::dropped},
    {"tiltgate_store_replayed_total", "counter",
     "Messages of the feed's store replayed to the broker once it was back, and acknowledged",
     &StoreStats::replayed},
};

}  // namespace

void add_store_families(MetricsExposition& out, const std::vector<FeedStoreStats>& stores) {
  if (stores.empty()) return;
  for (const StoreFamily& family : kStoreFamilies) {
    out.family(family.name, family.type, family.help);
    for (const FeedStoreStats& store : stores)
      out.sample("feed=\"" + metrics_label_value(store.feed) + "\"",
                 double(store.stats.*family.value));
  }
}

}  // namespace tiltgate
