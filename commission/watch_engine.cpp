#include "commission/watch_engine.h"

#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>

#include "commission/model_detection.h"
#include "commission/reading_format.h"

namespace tiltgate {

namespace {

namespace asio = boost::asio;

// The pause between rounds is waited out in slices, so a signal ends it promptly.
constexpr std::chrono::milliseconds kWaitSlice{50};

// What to tell of one sensor after a poll: why it gave no reading (an answer that is no reading;
// silence shows in its reading), and the model found.
std::string note_for(const CommissionBus& bus, const CommissionedSensor& sensor,
                     const PollOutcome& outcome, const std::string& model_found) {
  if (outcome.result != PollResult::refused && outcome.result != PollResult::no_reading)
    return model_found;
  const std::string why = poll_outcome_message(bus, sensor, outcome);
  return model_found.empty() ? why : why + "; " + model_found;
}

asio::awaitable<void> pause_until(SteadyClock::time_point until, const bool& stopping) {
  asio::steady_timer timer(co_await asio::this_coro::executor);
  while (!stopping && SteadyClock::now() < until) {
    timer.expires_after(std::min<SteadyClock::duration>(kWaitSlice, until - SteadyClock::now()));
    boost::system::error_code ec;
    co_await timer.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
}

// What watch keeps of one sensor from round to round.
struct Watched {
  ReadingRate rate;
  bool checked = false;     // its model is checked (or found) at its first poll with an answer
  std::string model_found;  // what the check found, to tell
};

// One poll of `sensor`, its model checked first until it answered once.
asio::awaitable<PollOutcome> poll_once(CommissionBus& bus, CommissionedSensor& sensor,
                                       Watched& watched, const bool& stopping) {
  if (watched.checked) {
    const PollMark before = mark_before_poll(sensor.driver->state());
    co_await sensor.driver->poll(bus.line());
    co_return outcome_since(before, sensor.driver->state());
  }
  const ModelCheck check = co_await check_model(bus, sensor, stopping);
  const PollOutcome outcome = check.outcome();
  watched.checked = outcome.result != PollResult::silent;
  watched.model_found = model_check_message(sensor, check);
  co_return outcome;
}

}  // namespace

UsageErrors watch_option_errors(const WatchOptions& options) {
  UsageErrors errors;
  if (options.count < 0 || options.count > kMaxWatchRounds)
    errors.push_back(fmt::format("--count: {} is not in 1..{} (0: until stopped)", options.count,
                                 kMaxWatchRounds));
  if (options.interval_ms < kMinWatchIntervalMs || options.interval_ms > kMaxWatchIntervalMs)
    errors.push_back(fmt::format("--interval: {} is not in {}..{} ms", options.interval_ms,
                                 kMinWatchIntervalMs, kMaxWatchIntervalMs));
  return errors;
}

asio::awaitable<int> watch_sensors(CommissionBus& bus, const WatchOptions& options,
                                   const EventSink& report, const bool& stopping) {
  const std::size_t count = bus.sensors().size();
  std::vector<Watched> watched(count);
  std::vector<std::string> notes(count);
  const std::chrono::milliseconds interval(options.interval_ms);
  for (int round = 1; !stopping; ++round) {
    const SteadyClock::time_point round_start = SteadyClock::now();
    WatchRoundEvent finished{round, {}, {}};
    for (std::size_t i = 0; i < count && !stopping; ++i) {
      CommissionedSensor& sensor = bus.sensors()[i];
      const PollOutcome outcome = co_await poll_once(bus, sensor, watched[i], stopping);
      if (stopping) break;
      watched[i].rate.update(sensor.driver->state());
      notes[i] = note_for(bus, sensor, outcome, watched[i].model_found);
      SensorReadingEvent reading = sensor_reading(sensor, outcome);
      reading.readings_per_second = watched[i].rate.per_second();
      report(reading);
      finished.readings.push_back(std::move(reading));
    }
    if (stopping) break;
    finished.notes = notes;
    report(finished);
    if (options.count > 0 && round >= options.count) break;
    co_await pause_until(round_start + interval, stopping);
  }
  co_return 0;
}

}  // namespace tiltgate
