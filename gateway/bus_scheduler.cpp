#include "gateway/bus_scheduler.h"

#include <algorithm>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

namespace tiltgate {

namespace asio = boost::asio;

BusScheduler::BusScheduler(asio::any_io_executor executor, Line& line, std::string name)
    : executor_(executor), line_(line), name_(std::move(name)), wake_(executor) {}

void BusScheduler::add(GatewaySensor& sensor) {
  sensor.bus = this;
  // The sensor arrives configured: its mounting and alarms are known from here on.
  sensor.processing = SensorProcessing(sensor.config.mounting, sensor.config.alarms);
  sensor.processed_seq = sensor.driver->state().sample_seq;
  sensors_.push_back({&sensor, SteadyClock::now()});
}

void BusScheduler::stop() {
  stopping_ = true;
  wake_.cancel();
  for (auto& pending : writes_) {
    pending->result = Unexpected(WriteError{WriteErrorKind::no_response, "gateway stopping"});
    pending->done.cancel();
  }
  writes_.clear();
}

BusScheduler::Polled* BusScheduler::next_due() {
  auto it = std::min_element(sensors_.begin(), sensors_.end(),
                             [](const Polled& a, const Polled& b) { return a.due < b.due; });
  return it == sensors_.end() ? nullptr : &*it;
}

void BusScheduler::reschedule(Polled& polled, SteadyClock::time_point now) {
  const auto period = polled.sensor->config.poll;
  if (polled.sensor->driver->state().online) {
    polled.failures = 0;
    // Keep the cadence while the bus keeps up; when it cannot, earliest-due-first shares it
    // round-robin instead of letting one sensor catch up in a burst.
    polled.due = std::max(polled.due + period, now);
    return;
  }
  // Offline: double the interval per failed poll, up to max_backoff, so a dead sensor costs
  // the bus one time-out every few seconds instead of one per poll period.
  polled.failures = std::min(polled.failures + 1, 16);
  auto wait = period * (1LL << std::min(polled.failures - 1, 10));
  polled.due = now + std::min<std::chrono::milliseconds>(
                         std::chrono::duration_cast<std::chrono::milliseconds>(wait), max_backoff);
}

asio::awaitable<void> BusScheduler::run() {
  while (!stopping_) {
    if (!writes_.empty()) {
      auto pending = writes_.front();
      writes_.pop_front();
      co_await run_write(pending);
      continue;
    }
    Polled* polled = next_due();
    auto now = SteadyClock::now();
    if (polled == nullptr || polled->due > now) {
      wake_.expires_at(polled ? polled->due : now + std::chrono::hours(1));
      boost::system::error_code ec;
      co_await wake_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
      continue;
    }
    co_await polled->sensor->driver->poll(line_);
    ++stats_.polls;
    process_new_reading(*polled->sensor);
    reschedule(*polled, SteadyClock::now());
  }
}

void BusScheduler::process_new_reading(GatewaySensor& sensor) {
  const SensorState& state = sensor.driver->state();
  if (state.sample_seq == sensor.processed_seq || !state.reading) return;
  sensor.processing.update(*state.reading);
  sensor.processed_seq = state.sample_seq;
}

asio::awaitable<void> BusScheduler::run_write(std::shared_ptr<PendingWrite> pending) {
  pending->started = true;
  auto result = co_await pending->sensor->driver->write(line_, pending->target, pending->value);
  ++stats_.writes;
  pending->result = std::move(result);
  pending->done.cancel();
}

asio::awaitable<WriteResult> BusScheduler::write(GatewaySensor& sensor, WriteTarget target,
                                                 double value, SteadyClock::time_point deadline) {
  if (stopping_) {
    co_return Unexpected(WriteError{WriteErrorKind::no_response, "gateway stopping"});
  }
  auto pending = std::make_shared<PendingWrite>(
      PendingWrite{&sensor, target, value, false, std::nullopt, asio::steady_timer(executor_)});
  writes_.push_back(pending);
  wake_.cancel();

  pending->done.expires_at(deadline);
  while (!pending->result) {
    boost::system::error_code ec;
    co_await pending->done.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    if (pending->result) break;
    if (ec != asio::error::operation_aborted) {  // the deadline passed
      if (!pending->started) {
        std::erase(writes_, pending);
        ++stats_.writes_expired;
        co_return Unexpected(WriteError{WriteErrorKind::busy, "bus too busy: write not started in time"});
      }
      // On the wire already: its own time-outs bound it, so wait for the end.
      pending->done.expires_at(SteadyClock::time_point::max());
    }
  }
  co_return std::move(*pending->result);
}

}  // namespace tiltgate
