// The backlog's replay while the broker is connected (docs/northbound.md, "MQTT", "Backlog"):
// one batch of the oldest messages at a time, at most `batch` of them a tick, published after
// the tick's live messages so a replay never holds a live state back. The batch leaves the
// backlog only once every message of it is acknowledged (QoS 1: its PUBACK), so a connection
// lost or a gateway stopped in between replays it again: at least once, never lost. Pure: the
// publishing is a function passed in.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "mqtt/mqtt_backlog.h"

namespace tiltgate {

class BacklogReplay {
 public:
  // Hands a message to the connection: its message id, none when it was not taken.
  using Publish = std::function<std::optional<int>(const MqttMessage&)>;

  explicit BacklogReplay(std::size_t batch) : batch_(batch) {}

  // Publishes the next batch when none is waiting for its acknowledgements.
  Expected<Done, std::string> step(MqttBacklog& backlog, const Publish& publish);
  // False for an id not of the batch. The batch's last one pops the batch off the backlog.
  Expected<bool, std::string> acknowledged(int mid, MqttBacklog& backlog);
  // The connection is gone, or the backlog changed under the batch (an append may drop its
  // oldest): the next step() starts again from the oldest.
  void cancel();
  bool waiting() const { return sent_ > 0; }
  std::uint64_t published() const { return published_; }  // messages handed over, repeats too

 private:
  std::size_t batch_;
  std::vector<int> unacknowledged_;  // ids of the batch still waited for
  std::size_t sent_ = 0;             // the batch: the oldest `sent_` of the backlog
  std::uint64_t published_ = 0;
};

}  // namespace tiltgate
