// A device server port's states (device_server/network_port_state.h): every move from every
// state against the table written out here, and a port's life through an outage.
#include <doctest/doctest.h>

#include <array>
#include <optional>

#include "device_server/network_port_state.h"

using namespace tiltgate;
using namespace tiltgate::network_port_state;
using E = NetworkPortEvent;

namespace {

const std::array<NetworkPortState, 7> kStates{Closed{},        Opening{false}, Opening{true},
                                              Reconnecting{false}, Reconnecting{true}, Open{},
                                              Stopped{}};
constexpr std::array kEvents{E::open_asked,     E::lost,       E::attempt_failed,
                             E::connected,      E::stop_asked, E::deadline_armed,
                             E::deadline_passed};

bool connecting(const NetworkPortState& state) {
  return std::holds_alternative<Opening>(state) || std::holds_alternative<Reconnecting>(state);
}

// The legal moves; every other pair is refused.
std::optional<NetworkPortState> expected_move(const NetworkPortState& state, E event) {
  const bool closed = std::holds_alternative<Closed>(state);
  const bool open = std::holds_alternative<Open>(state);
  const bool stopped = std::holds_alternative<Stopped>(state);
  if (event == E::stop_asked && !stopped) return Stopped{};
  if (closed && event == E::open_asked) return Opening{};
  if ((closed || open) && event == E::lost) return Reconnecting{};
  if (connecting(state) && event == E::attempt_failed) return Reconnecting{};
  if (connecting(state) && event == E::connected) return Open{};
  if (std::holds_alternative<Opening>(state)) {
    if (event == E::deadline_armed) return Opening{false};
    if (event == E::deadline_passed) return Opening{true};
  }
  if (std::holds_alternative<Reconnecting>(state)) {
    if (event == E::deadline_armed) return Reconnecting{false};
    if (event == E::deadline_passed) return Reconnecting{true};
  }
  return std::nullopt;
}

}  // namespace

TEST_CASE("a device server port's state moves only as the table says, on every event") {
  for (std::size_t s = 0; s < kStates.size(); ++s) {
    for (const E event : kEvents) {
      CAPTURE(s);
      CAPTURE(int(event));
      CHECK(next_state(kStates[s], event) == expected_move(kStates[s], event));
    }
  }
}

TEST_CASE("a device server port: opening, an outage warned of once, open, lost, stopped") {
  NetworkPortStates port;
  CHECK_FALSE(port.is_open());
  CHECK_FALSE(port.opening());
  CHECK(port.on(E::open_asked));
  CHECK(port.opening());  // an exchange waits for the first connect
  CHECK_FALSE(port.on(E::open_asked));  // one connect at a time
  CHECK_FALSE(port.on(E::lost));        // a loss while connecting: the connect goes on
  CHECK(port.opening());
  CHECK(port.on(E::deadline_armed));
  CHECK_FALSE(port.deadline_passed());
  CHECK(port.on(E::deadline_passed));
  CHECK(port.deadline_passed());
  CHECK(port.on(E::attempt_failed));
  CHECK(port.reconnecting());  // the first failure is the one warned of
  CHECK_FALSE(port.opening());
  CHECK_FALSE(port.deadline_passed());  // the next attempt starts afresh
  CHECK(port.on(E::attempt_failed));
  CHECK(port.reconnecting());
  CHECK(port.on(E::connected));
  CHECK(port.is_open());
  CHECK_FALSE(port.deadline_passed());
  CHECK_FALSE(port.on(E::deadline_passed));  // a late timer changes nothing once open
  CHECK_FALSE(port.on(E::open_asked));
  CHECK(port.is_open());
  CHECK(port.on(E::lost));
  CHECK(port.reconnecting());
  CHECK_FALSE(port.is_open());
  CHECK(port.on(E::stop_asked));
  CHECK(port.stopped());
  CHECK_FALSE(port.on(E::connected));  // a connect that ends after the stop is dropped
  CHECK_FALSE(port.on(E::open_asked));
  CHECK_FALSE(port.on(E::lost));
  CHECK(port.stopped());
  CHECK_FALSE(port.is_open());
}

TEST_CASE("a device server port stopped while its first connect is under way no longer opens") {
  NetworkPortStates port;
  CHECK(port.on(E::open_asked));
  CHECK(port.on(E::stop_asked));
  CHECK_FALSE(port.opening());
  CHECK(port.stopped());
  CHECK_FALSE(port.on(E::attempt_failed));
}
