// A command's transaction on a line it shares with a running gateway's polls (control/
// served_bus_line.h): each attempt is a turn of its own, with the gateway's polls
// between them, so retries are made here and every attempt goes with none; and after a time-out
// the line stays quiet for at most kMaxCommandLateGuard before the gateway polls again (a reply
// later than that reaches the next poll, whose framer drops it: it is from another address).
#pragma once

#include <algorithm>
#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <cstdint>

#include "driver/line.h"

namespace tiltgate {

// What a request that leaves them to the bus gets: the command's own bus settings (its
// time-out, retries and late guard), not the gateway's, so that a command behaves the same on
// its own tty and through a gateway.
struct CommandLineDefaults {
  std::chrono::milliseconds timeout{50};
  int retries = 2;
  std::chrono::milliseconds late_guard{450};
};

inline constexpr std::chrono::milliseconds kMaxCommandLateGuard{20};

// Runs `request` as attempts of `attempt(const LineRequest&)` (a coroutine with the Line's
// result), retrying after a time-out; `timing` is the line's, whose late replies add up.
template <class Attempt>
boost::asio::awaitable<Expected<Done, LineError>> transact_in_turns(
    LineRequest request, const CommandLineDefaults& defaults, LineTiming& timing,
    Attempt attempt) {
  if (request.timeout.count() <= 0) request.timeout = defaults.timeout;
  const int retries = request.retries < 0 ? defaults.retries : request.retries;
  request.retries = 0;
  request.late_guard =
      std::min(request.late_guard.value_or(defaults.late_guard), kMaxCommandLateGuard);
  std::uint32_t late_replies = 0;
  for (int attempt_number = 0;; ++attempt_number) {
    auto done = co_await attempt(request);
    late_replies += timing.late_replies;
    timing.late_replies = late_replies;
    if (done || done.error() != LineError::timeout || attempt_number >= retries) co_return done;
  }
}

}  // namespace tiltgate
