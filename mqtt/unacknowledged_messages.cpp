#include "mqtt/unacknowledged_messages.h"

#include <algorithm>

namespace tiltgate {

std::vector<MqttMessage> UnacknowledgedMessages::sent(int mid, MqttMessage message) {
  waiting_.emplace_back(mid, std::move(message));
  std::vector<MqttMessage> given_up;
  while (waiting_.size() > kLimit) {
    given_up.push_back(std::move(waiting_.front().second));
    waiting_.pop_front();
  }
  return given_up;
}

bool UnacknowledgedMessages::acknowledged(int mid) {
  // Acknowledgements come in the order sent: the match is nearly always the first.
  const auto it = std::find_if(waiting_.begin(), waiting_.end(),
                               [mid](const auto& entry) { return entry.first == mid; });
  if (it == waiting_.end()) return false;
  waiting_.erase(it);
  return true;
}

std::vector<MqttMessage> UnacknowledgedMessages::take_all() {
  std::vector<MqttMessage> all;
  all.reserve(waiting_.size());
  for (auto& entry : waiting_) all.push_back(std::move(entry.second));
  waiting_.clear();
  return all;
}

}  // namespace tiltgate
