// The feeds' stores in /metrics (status/store_metrics.h): four families, each HELP and TYPE
// once, one sample per feed labelled feed="..."; nothing without a store.
#include <doctest/doctest.h>

#include "status/status_metrics.h"
#include "status/store_metrics.h"

using namespace tiltgate;

namespace {

std::size_t count(const std::string& text, const std::string& part) {
  std::size_t n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("metrics: each feed's store gives its four series, each family's HELP and TYPE once") {
  MetricsExposition out;
  add_store_families(out, {{"mqtt", {4096, 12, 3, 40}}, {"sparkplug", {8, 0, 0, 7}}});
  const std::string text = out.take();
  CHECK(text.find("# TYPE tiltgate_store_bytes gauge\n") != std::string::npos);
  CHECK(text.find("# TYPE tiltgate_store_records gauge\n") != std::string::npos);
  CHECK(text.find("# TYPE tiltgate_store_dropped_total counter\n") != std::string::npos);
  CHECK(text.find("# TYPE tiltgate_store_replayed_total counter\n") != std::string::npos);
  CHECK(text.find("tiltgate_store_bytes{feed=\"mqtt\"} 4096\n") != std::string::npos);
  CHECK(text.find("tiltgate_store_records{feed=\"mqtt\"} 12\n") != std::string::npos);
  CHECK(text.find("tiltgate_store_dropped_total{feed=\"mqtt\"} 3\n") != std::string::npos);
  CHECK(text.find("tiltgate_store_replayed_total{feed=\"mqtt\"} 40\n") != std::string::npos);
  CHECK(text.find("tiltgate_store_replayed_total{feed=\"sparkplug\"} 7\n") != std::string::npos);
  CHECK(count(text, "# HELP tiltgate_store_") == 4);
  CHECK(count(text, "# TYPE tiltgate_store_") == 4);
}

TEST_CASE("metrics: no store, no tiltgate_store_ series; the gateway's text has the feeds' stores") {
  GatewayStatus status;
  CHECK(metrics_text(status).find("tiltgate_store_") == std::string::npos);
  status.stores.push_back({"mqtt", {100, 2, 1, 5}});
  CHECK(metrics_text(status).find("tiltgate_store_records{feed=\"mqtt\"} 2\n") !=
        std::string::npos);
}
