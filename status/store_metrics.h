// The feeds' store-and-forward backlogs in /metrics (docs/northbound.md, "HTTP status API and
// metrics"): tiltgate_store_bytes, _records, _dropped_total and _replayed_total, each family's
// HELP and TYPE once and one sample per feed (feed="mqtt", feed="sparkplug"). Pure.
#pragma once

#include <vector>

#include "gateway/gateway_status.h"
#include "status/metrics_exposition.h"

namespace tiltgate {

// Nothing for no store.
void add_store_families(MetricsExposition& out, const std::vector<FeedStoreStats>& stores);

}  // namespace tiltgate
