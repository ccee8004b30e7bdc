// The feed's backlog in memory (mqtt/mqtt_backlog.h): used when the state directory cannot be
// used (docs/operations.md, "The state directory"), and lost when the gateway stops. The same
// limits as on disk: the payloads' and topics' bytes, and the message count when given.
#pragma once

#include <deque>

#include "mqtt/mqtt_backlog.h"

namespace tiltgate {

class MemoryBacklog final : public MqttBacklog {
 public:
  explicit MemoryBacklog(BacklogLimits limits) : limits_(limits) {}

  Expected<Done, std::string> append(const MqttMessage& message) override;
  Expected<std::vector<MqttMessage>, std::string> peek(std::size_t n) override;
  Expected<Done, std::string> pop(std::size_t n) override;
  Expected<Done, std::string> sync() override { return Done{}; }
  StoreStats stats() const override;

 private:
  void drop_front();

  BacklogLimits limits_;
  std::deque<MqttMessage> messages_;
  std::uint64_t bytes_ = 0;
  std::uint64_t dropped_ = 0;
  std::uint64_t replayed_ = 0;
};

}  // namespace tiltgate
