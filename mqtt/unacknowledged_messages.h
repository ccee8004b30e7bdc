// Live messages handed to the broker connection and not yet acknowledged (a PUBACK at QoS 1,
// PUBCOMP at 2; written to the socket at 0), in the order they were sent. When the connection
// is lost they go to the backlog (docs/northbound.md, "MQTT", "Backlog"): what the broker may
// not have received is replayed (at least once) rather than lost. Pure.
#pragma once

#include <cstddef>
#include <deque>
#include <utility>
#include <vector>

#include "mqtt/mqtt_message.h"

namespace tiltgate {

class UnacknowledgedMessages {
 public:
  // More than this many outstanding is a broker that stopped answering; the oldest are then
  // given back by sent() (libmosquitto's message ids are 16 bits: far fewer than that).
  static constexpr std::size_t kLimit = 10000;

  // `message` went out with id `mid`; returns the oldest given up on when over kLimit.
  std::vector<MqttMessage> sent(int mid, MqttMessage message);
  // False for an id not waited for (the status, a replayed message).
  bool acknowledged(int mid);
  // Every one still waiting, oldest first; none waits afterwards.
  std::vector<MqttMessage> take_all();
  std::size_t size() const { return waiting_.size(); }

 private:
  std::deque<std::pair<int, MqttMessage>> waiting_;
};

}  // namespace tiltgate
