#include "gateway/bus_scheduler.h"

#include <algorithm>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace tiltgate {

namespace {

// Waits until the bus has carried out `pending` (a queued write or forwarded request): true
// once its result is set. False when `deadline` passed before it started: it is taken out of
// `queue` and never sent. One already on the wire is always waited for, since the bus's own
// time-outs bound it.
template <class Pending>
boost::asio::awaitable<bool> wait_for_result(std::deque<std::shared_ptr<Pending>>& queue,
                                             std::shared_ptr<Pending> pending,
                                             SteadyClock::time_point deadline) {
  pending->done.expires_at(deadline);
  while (!pending->result) {
    boost::system::error_code ec;
    co_await pending->done.async_wait(
        boost::asio::redirect_error(boost::asio::use_awaitable, ec));
    if (pending->result) break;
    if (ec != boost::asio::error::operation_aborted) {  // the deadline passed
      if (!pending->started) {
        std::erase(queue, pending);
        co_return false;
      }
      pending->done.expires_at(SteadyClock::time_point::max());
    }
  }
  co_return true;
}

WriteError stopping_write() { return WriteError{WriteErrorKind::no_response, "gateway stopping"}; }

CommandExchangeResult failed_exchange(LineError error) {
  CommandExchangeResult result;
  result.done = Unexpected{error};
  return result;
}

}  // namespace

namespace asio = boost::asio;

BusScheduler::BusScheduler(asio::any_io_executor executor, Line& line, std::string name)
    : executor_(executor), line_(line), name_(std::move(name)), wake_(executor) {}

void BusScheduler::add(GatewaySensor& sensor) {
  // An empty owner: a pointer that keeps nothing alive.
  add(std::shared_ptr<GatewaySensor>(std::shared_ptr<GatewaySensor>(), &sensor));
}

void BusScheduler::add(std::shared_ptr<GatewaySensor> sensor) {
  sensor->bus = this;
  // The sensor arrives configured: its mounting and alarms are known from here on.
  sensor->processing = SensorProcessing(sensor->config.mounting, sensor->config.alarms);
  sensor->processed_seq = sensor->driver->state().sample_seq;
  sensor->publish();
  sensors_.push_back({std::move(sensor), PollSchedule{SteadyClock::now()}});
  wake_.cancel();
}

void BusScheduler::remove(const GatewaySensor& sensor) {
  std::erase_if(sensors_, [&](const Polled& polled) { return polled.sensor.get() == &sensor; });
}

void BusScheduler::retire() {
  retiring_ = true;
  sensors_.clear();
  refuse_queued_turns();
  wake_.cancel();
}

BusScheduler::Polled* BusScheduler::find_polled(const GatewaySensor* sensor) {
  for (Polled& polled : sensors_)
    if (polled.sensor.get() == sensor) return &polled;
  return nullptr;
}

const char* to_string(ForwardFailure failure) {
  switch (failure) {
    case ForwardFailure::busy: return "bus too busy: forward queue full";
    case ForwardFailure::expired: return "bus too busy: not sent in time";
    case ForwardFailure::no_response: return "no reply";
    case ForwardFailure::unframed: return "cannot be forwarded on this bus";
  }
  return "unknown";
}

void BusScheduler::stop() {
  stopping_ = true;
  wake_.cancel();
  for (auto& pending : writes_) {
    pending->result = pending->write.fail(stopping_write());
    pending->done.cancel();
  }
  writes_.clear();
  refuse_queued_turns();
}

void BusScheduler::refuse_queued_turns() {
  for (auto& pending : forwards_) {
    pending->result = Unexpected{ForwardFailure::no_response};
    pending->done.cancel();
  }
  forwards_.clear();
  for (auto& pending : commands_) {
    pending->result = failed_exchange(LineError::cancelled);
    pending->done.cancel();
  }
  commands_.clear();
}

void BusScheduler::enable_forwarding(ForwardFactory make, std::size_t max_queued) {
  make_forward_ = make;
  max_queued_forwards_ = max_queued;
}

namespace {

// When a sensor is next polled: its schedule, or after a command's hold on it.
SteadyClock::time_point due_of(const PollSchedule& schedule,
                               const std::optional<SteadyClock::time_point>& held_until) {
  return held_until ? std::max(schedule.due, *held_until) : schedule.due;
}

// Adds the time from its construction to its destruction to `total`: wrapped around each
// turn on the line, it sums the time the bus was busy.
class BusyTime {
 public:
  explicit BusyTime(std::chrono::nanoseconds& total) : total_(total) {}
  ~BusyTime() { total_ += SteadyClock::now() - started_; }
  BusyTime(const BusyTime&) = delete;
  BusyTime& operator=(const BusyTime&) = delete;

 private:
  std::chrono::nanoseconds& total_;
  SteadyClock::time_point started_ = SteadyClock::now();
};

}  // namespace

BusScheduler::Polled* BusScheduler::next_due() {
  auto it = std::min_element(sensors_.begin(), sensors_.end(),
                             [](const Polled& a, const Polled& b) {
                               return due_of(a.schedule, a.held_until) <
                                      due_of(b.schedule, b.held_until);
                             });
  return it == sensors_.end() ? nullptr : &*it;
}

WriteResult BusScheduler::check_address_free(const GatewaySensor& sensor, WriteTarget target,
                                             double value) const {
  const auto address = sensor.driver->address_after(target, value);
  if (!address) return Done{};
  for (const Polled& other : sensors_) {
    // Drivers follow their sensor to a new address, so this is where each one answers now.
    if (other.sensor.get() == &sensor || other.sensor->driver->state().bus_address != *address) continue;
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
      const BusyTime busy(stats_.busy);
      co_await run_write(pending);
      continue;
    }
    if (retiring_) {  // its last queued write is done
      stop();
      break;
    }
    Polled* polled = next_due();
    auto now = SteadyClock::now();
    if (polled && polled->held_until && *polled->held_until <= now) polled->held_until.reset();
    const auto due = polled ? due_of(polled->schedule, polled->held_until) : now;
    const bool poll_due = polled != nullptr && due <= now;
    // Forwarded requests and due polls take turns: a client hammering a passed-through device
    // cannot starve the cached sensors, and a busy poll schedule cannot starve the client.
    if ((!forwards_.empty() || !commands_.empty()) && (!poll_due || !forwarded_last_)) {
      const BusyTime busy(stats_.busy);
      co_await run_turn();
      forwarded_last_ = true;
      continue;
    }
    if (!poll_due) {
      wake_.expires_at(polled ? due : now + std::chrono::hours(1));
      boost::system::error_code ec;
      co_await wake_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
      continue;
    }
    // Held here: a reload may remove the sensor, or add others, while its poll is on the wire.
    const std::shared_ptr<GatewaySensor> sensor = polled->sensor;
    {
      const BusyTime busy(stats_.busy);
      co_await sensor->driver->poll(line_);
    }
    ++stats_.polls;
    forwarded_last_ = false;
    process_new_reading(*sensor);
    sensor->publish();
    polled = find_polled(sensor.get());
    if (polled == nullptr) continue;  // removed meanwhile
    polled->schedule = after_poll(polled->schedule, sensor->driver->state().online,
                                  sensor->config.poll, max_backoff, SteadyClock::now());
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
  pending->result = co_await pending->write.run(line_, *this, stats_.writes);
  pending->done.cancel();
}

asio::awaitable<WriteResult> BusScheduler::write(SensorWrite write,
                                                 SteadyClock::time_point deadline) {
  if (WriteResult admitted = write.admit(*this); !admitted) co_return admitted;
  if (stopping_) co_return write.fail(stopping_write());
  auto pending = std::make_shared<PendingWrite>(
      PendingWrite{std::move(write), false, std::nullopt, asio::steady_timer(executor_)});
  writes_.push_back(pending);
  wake_.cancel();

  if (!co_await wait_for_result(writes_, pending, deadline)) {
    ++stats_.writes_expired;
    co_return pending->write.fail(
        WriteError{WriteErrorKind::busy, "bus too busy: write not started in time"});
  }
  co_return std::move(*pending->result);
}

asio::awaitable<ForwardResult> BusScheduler::exchange(const PendingForward& pending) {
  if (make_forward_ == nullptr) {
    ++stats_.forwards_unframed;
    co_return Unexpected{ForwardFailure::unframed};
  }
  auto made = make_forward_(pending.slave, pending.pdu);
  if (!made) {
    ++stats_.forwards_unframed;
    spdlog::warn("{}: request for slave {} not forwarded: {}", name_, pending.slave, made.error());
    co_return Unexpected{ForwardFailure::unframed};
  }
  ForwardedExchange& forwarded = **made;
  LineRequest request;
  request.bytes = forwarded.request_bytes();
  request.framer = &forwarded.framer();
  request.timeout = std::chrono::milliseconds(0);  // the bus's reply time-out
  request.retries = 0;  // the client retries; a forwarded write must never run twice
  auto done = co_await line_.transact(std::move(request));
  if (!done) {
    ++stats_.forward_timeouts;
    spdlog::debug("{}: forwarded request to slave {}: {}", name_, pending.slave,
                  to_string(done.error()));
    co_return Unexpected{ForwardFailure::no_response};
  }
  auto reply = forwarded.reply_pdu();
  if (!reply) {
    ++stats_.forward_timeouts;
    spdlog::debug("{}: forwarded request to slave {}: {}", name_, pending.slave, reply.error());
    co_return Unexpected{ForwardFailure::no_response};
  }
  ++stats_.forwarded;
  co_return std::move(*reply);
}

asio::awaitable<void> BusScheduler::run_turn() {
  if (!commands_.empty() && (forwards_.empty() || !command_last_)) {
    auto pending = commands_.front();
    commands_.pop_front();
    command_last_ = true;
    pending->started = true;
    CommandExchangeResult result;
    result.done = co_await line_.transact(pending->request);
    result.timing = line_.last_timing();
    result.generation = line_.generation();
    ++stats_.command_exchanges;
    pending->result = std::move(result);
    pending->done.cancel();
    co_return;
  }
  auto pending = forwards_.front();
  forwards_.pop_front();
  command_last_ = false;
  co_await run_forward(pending);
}

asio::awaitable<CommandExchangeResult> BusScheduler::exchange_for_command(
    LineRequest request, SteadyClock::time_point deadline) {
  if (stopping_ || retiring_) co_return failed_exchange(LineError::cancelled);
  auto pending = std::make_shared<PendingCommand>(
      PendingCommand{std::move(request), false, std::nullopt, asio::steady_timer(executor_)});
  commands_.push_back(pending);
  wake_.cancel();
  if (!co_await wait_for_result(commands_, pending, deadline)) {
    ++stats_.command_exchanges_expired;
    CommandExchangeResult expired = failed_exchange(LineError::timeout);
    expired.expired = true;
    co_return expired;
  }
  co_return std::move(*pending->result);
}

std::optional<std::string> BusScheduler::follow_address(std::uint32_t from, std::uint32_t to) {
  for (Polled& polled : sensors_) {
    SensorDriver& driver = *polled.sensor->driver;
    if (driver.state().bus_address != from) continue;
    driver.follow_address(to);
    polled.sensor->publish();
    // Poll it at its new address at once: the command's read-back and the PLC agree sooner.
    polled.schedule = PollSchedule{SteadyClock::now()};
    polled.held_until.reset();
    wake_.cancel();
    spdlog::info("{}: sensor \"{}\" moved from address {} to {} by a commissioning command",
                 name_, polled.sensor->config.name, from, to);
    return polled.sensor->config.name;
  }
  return std::nullopt;
}

std::optional<std::string> BusScheduler::hold(std::uint32_t address,
                                              SteadyClock::time_point until) {
  for (Polled& polled : sensors_) {
    if (polled.sensor->driver->state().bus_address != address) continue;
    polled.held_until = until;
    return polled.sensor->config.name;
  }
  return std::nullopt;
}

void BusScheduler::release(std::uint32_t address) {
  for (Polled& polled : sensors_)
    if (polled.held_until && polled.sensor->driver->state().bus_address == address) {
      polled.held_until.reset();
      wake_.cancel();
    }
}

asio::awaitable<void> BusScheduler::run_forward(std::shared_ptr<PendingForward> pending) {
  pending->started = true;
  pending->result = co_await exchange(*pending);
  pending->done.cancel();
}

asio::awaitable<ForwardResult> BusScheduler::forward(std::uint8_t slave,
                                                     std::vector<std::uint8_t> pdu,
                                                     SteadyClock::time_point deadline) {
  if (stopping_ || retiring_) co_return Unexpected{ForwardFailure::no_response};
  if (forwards_.size() >= max_queued_forwards_) {
    ++stats_.forwards_busy;
    co_return Unexpected{ForwardFailure::busy};
  }
  auto pending = std::make_shared<PendingForward>(PendingForward{
      slave, std::move(pdu), false, std::nullopt, asio::steady_timer(executor_)});
  forwards_.push_back(pending);
  wake_.cancel();

  if (!co_await wait_for_result(forwards_, pending, deadline)) {
    ++stats_.forwards_expired;
    co_return Unexpected{ForwardFailure::expired};
  }
  co_return std::move(*pending->result);
}

}  // namespace tiltgate
