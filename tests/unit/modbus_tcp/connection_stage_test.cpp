// A Modbus TCP connection's stages (modbus_tcp/connection_stage.h): every move from every
// stage against the table written out here, and the life of a plain and of a TLS connection.
#include <doctest/doctest.h>

#include <array>
#include <optional>
#include <string>

#include "modbus_tcp/connection_stage.h"

using namespace tiltgate;
using S = ConnectionStage;
using E = ConnectionEvent;

namespace {

constexpr std::array kStages{S::accepted, S::handshaking, S::serving, S::with_handler, S::ended};
constexpr std::array kEvents{E::watched_plain, E::watched_tls,  E::handshake_done,
                             E::handed_over,   E::handler_done, E::closed};

// The legal moves; every other pair is refused.
std::optional<S> expected_move(S stage, E event) {
  if (stage == S::accepted && event == E::watched_plain) return S::serving;
  if (stage == S::accepted && event == E::watched_tls) return S::handshaking;
  if (stage == S::handshaking && event == E::handshake_done) return S::serving;
  if (stage == S::serving && event == E::handed_over) return S::with_handler;
  if (stage == S::with_handler && event == E::handler_done) return S::serving;
  if (stage != S::ended && event == E::closed) return S::ended;
  return std::nullopt;
}

}  // namespace

TEST_CASE("a connection's stage moves only as the table says, from every stage on every event") {
  for (const S stage : kStages) {
    for (const E event : kEvents) {
      CAPTURE(int(stage));
      CAPTURE(int(event));
      CHECK(next_stage(stage, event) == expected_move(stage, event));
    }
  }
}

TEST_CASE("a plain connection serves at once, waits for its handler, and ends once") {
  ConnectionStages stages;
  CHECK(stages.is(S::accepted));
  CHECK_FALSE(is_watched(stages.stage()));
  CHECK_FALSE(stages.on(E::handed_over));  // nothing is answered before it is watched
  CHECK(stages.on(E::watched_plain));
  CHECK(stages.is(S::serving));
  CHECK(is_watched(stages.stage()));
  CHECK_FALSE(stages.on(E::handshake_done));  // a plain stream has no handshake
  CHECK(stages.on(E::handed_over));
  CHECK(stages.is(S::with_handler));
  CHECK_FALSE(stages.on(E::handed_over));  // one request with the handler at a time
  CHECK(stages.is(S::with_handler));
  CHECK(stages.on(E::handler_done));
  CHECK(stages.is(S::serving));
  CHECK_FALSE(stages.on(E::handler_done));  // a second reply to the same request is dropped
  CHECK(stages.on(E::closed));
  CHECK(stages.is(S::ended));
  CHECK_FALSE(is_watched(stages.stage()));
  CHECK_FALSE(stages.on(E::closed));  // it ends once
  CHECK_FALSE(stages.on(E::handler_done));  // a reply after the end changes nothing
  CHECK(stages.is(S::ended));
}

TEST_CASE("a TLS connection serves only after its handshake") {
  ConnectionStages stages;
  CHECK(stages.on(E::watched_tls));
  CHECK(stages.is(S::handshaking));
  CHECK(is_watched(stages.stage()));
  CHECK_FALSE(stages.on(E::handed_over));
  CHECK(stages.is(S::handshaking));
  CHECK(stages.on(E::handshake_done));
  CHECK(stages.is(S::serving));
}

TEST_CASE("a connection closed before its loop watched it ends without having been watched") {
  ConnectionStages stages;
  CHECK_FALSE(is_watched(stages.stage()));
  CHECK(stages.on(E::closed));
  CHECK(stages.is(S::ended));
  CHECK_FALSE(stages.on(E::watched_plain));  // its loop takes it up too late
  CHECK(stages.is(S::ended));
}
