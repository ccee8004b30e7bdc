// The backlog's replay (mqtt/backlog_replay.h) and the live messages waiting for their
// acknowledgement (mqtt/unacknowledged_messages.h): a batch at a time, popped only once every
// message of it is acknowledged, started again from the oldest after a lost connection, and
// the unacknowledged live messages given back in order.
#include <doctest/doctest.h>

#include <optional>
#include <string>
#include <vector>

#include "mqtt/backlog_replay.h"
#include "mqtt/memory_backlog.h"
#include "mqtt/unacknowledged_messages.h"

using namespace tiltgate;

namespace {

MqttMessage state(int i) { return {"gw/s/state", std::to_string(i), false, 1000 + i}; }

MemoryBacklog filled(int count) {
  MemoryBacklog backlog({1024 * 1024, std::nullopt});
  for (int i = 0; i < count; ++i) REQUIRE(backlog.append(state(i)).has_value());
  return backlog;
}

// A connection that takes messages, numbering them from 1, and remembers what it was given.
struct FakeConnection {
  std::vector<std::string> sent;
  int next_mid = 1;
  bool up = true;
  BacklogReplay::Publish publish() {
    return [this](const MqttMessage& m) -> std::optional<int> {
      if (!up) return std::nullopt;
      sent.push_back(m.payload);
      return next_mid++;
    };
  }
};

}  // namespace

TEST_CASE("mqtt replay: one batch of the oldest at a time, popped when all of it is acknowledged") {
  MemoryBacklog backlog = filled(7);
  BacklogReplay replay(3);
  FakeConnection connection;
  REQUIRE(replay.step(backlog, connection.publish()).has_value());
  CHECK(connection.sent == std::vector<std::string>{"0", "1", "2"});
  REQUIRE(replay.step(backlog, connection.publish()).has_value());  // waits for the batch
  CHECK(connection.sent.size() == 3);
  // Acknowledged out of order, and an id that is not the batch's.
  CHECK(*replay.acknowledged(2, backlog));
  CHECK_FALSE(*replay.acknowledged(99, backlog));
  CHECK(*replay.acknowledged(1, backlog));
  CHECK(backlog.stats().records == 7);  // not before the last
  CHECK(*replay.acknowledged(3, backlog));
  CHECK(backlog.stats().records == 4);
  CHECK(backlog.stats().replayed == 3);
  REQUIRE(replay.step(backlog, connection.publish()).has_value());
  CHECK(connection.sent.back() == "5");
  CHECK(replay.published() == 6);
}

TEST_CASE("mqtt replay: a lost connection replays the batch again from the oldest") {
  MemoryBacklog backlog = filled(5);
  BacklogReplay replay(2);
  FakeConnection connection;
  REQUIRE(replay.step(backlog, connection.publish()).has_value());
  CHECK(*replay.acknowledged(1, backlog));
  replay.cancel();  // the connection went before message 2 was acknowledged
  CHECK_FALSE(*replay.acknowledged(2, backlog));  // a late one changes nothing
  CHECK(backlog.stats().records == 5);
  REQUIRE(replay.step(backlog, connection.publish()).has_value());
  CHECK(connection.sent == std::vector<std::string>{"0", "1", "0", "1"});  // at least once
}

TEST_CASE("mqtt replay: a batch cut short by a refused publish pops only what went out") {
  MemoryBacklog backlog = filled(5);
  BacklogReplay replay(4);
  FakeConnection connection;
  int left = 2;
  const BacklogReplay::Publish two = [&](const MqttMessage& m) -> std::optional<int> {
    if (left-- <= 0) return std::nullopt;
    return connection.publish()(m);
  };
  REQUIRE(replay.step(backlog, two).has_value());
  CHECK(connection.sent.size() == 2);
  CHECK(*replay.acknowledged(1, backlog));
  CHECK(*replay.acknowledged(2, backlog));
  CHECK(backlog.stats().records == 3);
  REQUIRE(replay.step(backlog, connection.publish()).has_value());
  CHECK(connection.sent == std::vector<std::string>{"0", "1", "2", "3", "4"});
}

TEST_CASE("mqtt replay: nothing is published while the backlog is empty") {
  MemoryBacklog backlog = filled(0);
  BacklogReplay replay(4);
  FakeConnection connection;
  REQUIRE(replay.step(backlog, connection.publish()).has_value());
  CHECK(connection.sent.empty());
  CHECK_FALSE(replay.waiting());
}

TEST_CASE("mqtt unacknowledged: acknowledged ones go, the rest come back oldest first") {
  UnacknowledgedMessages waiting;
  for (int i = 0; i < 4; ++i) CHECK(waiting.sent(10 + i, state(i)).empty());
  CHECK(waiting.acknowledged(11));
  CHECK_FALSE(waiting.acknowledged(11));
  CHECK_FALSE(waiting.acknowledged(7));
  const std::vector<MqttMessage> left = waiting.take_all();
  REQUIRE(left.size() == 3);
  CHECK(left[0] == state(0));
  CHECK(left[1] == state(2));
  CHECK(left[2] == state(3));
  CHECK(waiting.size() == 0);
}

TEST_CASE("mqtt unacknowledged: past its limit the oldest is given back, not forgotten") {
  UnacknowledgedMessages waiting;
  for (std::size_t i = 0; i < UnacknowledgedMessages::kLimit; ++i)
    CHECK(waiting.sent(int(i % 65535) + 1, state(int(i))).empty());
  const std::vector<MqttMessage> given_up = waiting.sent(1, state(-1));
  REQUIRE(given_up.size() == 1);
  CHECK(given_up[0] == state(0));
  CHECK(waiting.size() == UnacknowledgedMessages::kLimit);
}
