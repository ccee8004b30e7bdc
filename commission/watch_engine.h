// `watch` as the engine runs it, for every front end: the vendor's Multi-Unit Angle Display.
// Each sensor is polled in turn through its driver, its model checked (or found) at its first
// answer (commission/model_detection.h), round after round. Each poll is a SensorReadingEvent
// and each round a WatchRoundEvent (commission/commission_events.h); nothing is printed.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <cstdint>

#include "commission/commission_bus.h"
#include "commission/commission_events.h"
#include "commission/commission_options.h"

namespace tiltgate {

struct WatchOptions {
  int count = 0;  // rounds before stopping; 0: until `stopping`
  int interval_ms = 500;  // from the start of one round to the next
};

// What each front end accepts: --count 1.., --interval from 10 ms (about one sensor's poll at
// the fastest rates; a longer round simply starts the next at once) to an hour.
inline constexpr int kMaxWatchRounds = 100'000'000;
inline constexpr int kMinWatchIntervalMs = 10;
inline constexpr int kMaxWatchIntervalMs = 3'600'000;

// The options checked against those ranges; every error names its option. Empty: fine.
UsageErrors watch_option_errors(const WatchOptions& options);

// Polls the sensors of `bus` round after round and returns the exit code: 0 (a sensor that
// does not answer shows as such in its readings).
boost::asio::awaitable<int> watch_sensors(CommissionBus& bus, const WatchOptions& options,
                                          const EventSink& report, const bool& stopping);

}  // namespace tiltgate
