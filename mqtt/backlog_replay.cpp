#include "mqtt/backlog_replay.h"

#include <algorithm>

namespace tiltgate {

Expected<Done, std::string> BacklogReplay::step(MqttBacklog& backlog, const Publish& publish) {
  if (waiting() || backlog.empty()) return Done{};
  auto batch = backlog.peek(batch_);
  if (!batch) return Unexpected(batch.error());
  for (const MqttMessage& message : *batch) {
    const std::optional<int> mid = publish(message);
    if (!mid) break;  // the rest of the batch waits for the next one
    unacknowledged_.push_back(*mid);
    ++sent_;
    ++published_;
  }
  return Done{};
}

Expected<bool, std::string> BacklogReplay::acknowledged(int mid, MqttBacklog& backlog) {
  const auto it = std::find(unacknowledged_.begin(), unacknowledged_.end(), mid);
  if (it == unacknowledged_.end()) return false;
  unacknowledged_.erase(it);
  if (!unacknowledged_.empty()) return true;
  const std::size_t done = sent_;
  sent_ = 0;
  if (auto popped = backlog.pop(done); !popped) return Unexpected(popped.error());
  return true;
}

void BacklogReplay::cancel() {
  unacknowledged_.clear();
  sent_ = 0;
}

}  // namespace tiltgate
