#include "gateway/bus_scheduler.h"

#include <algorithm>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>
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
  sensors_.push_back({&sensor, PollSchedule{SteadyClock::now()}});
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
                             [](const Polled& a, const Polled& b) {
                               return a.schedule.due < b.schedule.due;
                             });
  return it == sensors_.end() ? nullptr : &*it;
}

WriteResult BusScheduler::check_address_free(const GatewaySensor& sensor, WriteTarget target,
                                             double value) const {
  const auto address = sensor.driver->address_after(target, value);
  if (!address) return Done{};
  for (const Polled& other : sensors_) {
    // Drivers follow their sensor to a new address, so this is where each one answers now.
    if (other.sensor == &sensor || other.sensor->driver->state().bus_address != *address) continue;
    return Unexpected{WriteError{
        WriteErrorKind::bad_value,
        fmt::format("address {} is taken by sensor \"{}\" on bus \"{}\"", *address,
                    other.sensor->config.name, name_)}};
  }
  return Done{};
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
    if (polled == nullptr || polled->schedule.due > now) {
      wake_.expires_at(polled ? polled->schedule.due : now + std::chrono::hours(1));
      boost::system::error_code ec;
      co_await wake_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
      continue;
    }
    co_await polled->sensor->driver->poll(line_);
    ++stats_.polls;
    process_new_reading(*polled->sensor);
    polled->schedule = after_poll(polled->schedule, polled->sensor->driver->state().online,
                                  polled->sensor->config.poll, max_backoff, SteadyClock::now());
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
  // Again now: a write queued before this one may have moved a sensor to this address.
  WriteResult result = check_address_free(*pending->sensor, pending->target, pending->value);
  if (result) {
    result = co_await pending->sensor->driver->write(line_, pending->target, pending->value);
    ++stats_.writes;
  }
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
