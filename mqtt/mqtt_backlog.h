// What the JSON feed could not publish, kept until the broker is back (docs/northbound.md,
// "MQTT", "Backlog"): on disk in the store (mqtt/stored_backlog.h), or in memory when the state
// directory cannot be used (mqtt/memory_backlog.h). Oldest first; bounded by bytes (buffer_mb)
// and, when given, by messages (backlog), the oldest dropped and counted. One owner, the
// feed's event loop.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "gateway/gateway_status.h"
#include "mqtt/mqtt_message.h"
#include "store/record_store.h"

namespace tiltgate {

struct BacklogLimits {
  std::uint64_t bytes = 64ull * 1024 * 1024;  // [mqtt] buffer_mb
  std::optional<std::size_t> messages;       // [mqtt] backlog; none: bytes alone
};

class MqttBacklog {
 public:
  virtual ~MqttBacklog() = default;

  // Keeps `message` after the others, dropping the oldest when full. An error (a message too
  // large to keep): it is not kept, and counted as dropped.
  virtual Expected<Done, std::string> append(const MqttMessage& message) = 0;
  // The oldest `n` not yet replayed (fewer when there are fewer), in the order appended.
  virtual Expected<std::vector<MqttMessage>, std::string> peek(std::size_t n) = 0;
  // The oldest `n` were published and acknowledged: they go, and count as replayed.
  virtual Expected<Done, std::string> pop(std::size_t n) = 0;
  // What was appended is on the disk (a power cut no longer loses it).
  virtual Expected<Done, std::string> sync() = 0;
  virtual StoreStats stats() const = 0;
  // What the log should say about its disk since the last call (store/record_store.h).
  virtual std::vector<store::StoreNotice> take_notices() { return {}; }
  bool empty() const { return stats().records == 0; }
};

}  // namespace tiltgate
