#include "mqtt/memory_backlog.h"

#include <algorithm>

namespace tiltgate {

namespace {

std::uint64_t size_of(const MqttMessage& message) {
  return message.topic.size() + message.payload.size();
}

}  // namespace

void MemoryBacklog::drop_front() {
  bytes_ -= size_of(messages_.front());
  messages_.pop_front();
  ++dropped_;
}

Expected<Done, std::string> MemoryBacklog::append(const MqttMessage& message) {
  const std::uint64_t size = size_of(message);
  if (size > limits_.bytes || limits_.messages == std::size_t{0}) {
    ++dropped_;
    return Done{};
  }
  while (!messages_.empty() &&
         (bytes_ + size > limits_.bytes ||
          (limits_.messages && messages_.size() >= *limits_.messages)))
    drop_front();
  messages_.push_back(message);
  bytes_ += size;
  return Done{};
}

Expected<std::vector<MqttMessage>, std::string> MemoryBacklog::peek(std::size_t n) {
  const std::size_t count = std::min(n, messages_.size());
  return std::vector<MqttMessage>(messages_.begin(), messages_.begin() + std::ptrdiff_t(count));
}

Expected<Done, std::string> MemoryBacklog::pop(std::size_t n) {
  for (std::size_t i = 0; i < n && !messages_.empty(); ++i) {
    bytes_ -= size_of(messages_.front());
    messages_.pop_front();
    ++replayed_;
  }
  return Done{};
}

StoreStats MemoryBacklog::stats() const {
  StoreStats stats;
  stats.bytes = bytes_;
  stats.records = messages_.size();
  stats.dropped = dropped_;
  stats.replayed = replayed_;
  return stats;
}

}  // namespace tiltgate
