#include "gateway/bus_scheduler.h"

#include <algorithm>
#include <boost/asio/post.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

namespace tiltgate {

namespace asio = boost::asio;

BusScheduler::BusScheduler(asio::any_io_executor executor, Line& line, std::string name)
    : line_(line), name_(std::move(name)), jobs_(executor), wake_(executor) {}

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
  jobs_.refuse_turns();
  wake_.cancel();
}

BusScheduler::Polled* BusScheduler::find_polled(const GatewaySensor* sensor) {
  for (Polled& polled : sensors_)
    if (polled.sensor.get() == sensor) return &polled;
  return nullptr;
}

void BusScheduler::stop() {
  stopping_ = true;
  wake_.cancel();
  jobs_.refuse_all();
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
    Polled* polled = next_due();
    const auto now = SteadyClock::now();
    if (polled && polled->held_until && *polled->held_until <= now) polled->held_until.reset();
    const auto due = polled ? due_of(polled->schedule, polled->held_until) : now;
    const bool poll_due = polled != nullptr && due <= now;
    if (const std::shared_ptr<BusJob> job = jobs_.take(poll_due)) {
      co_await carry_out(*job);
      continue;
    }
    if (retiring_) {  // its last queued write is done
      stop();
      break;
    }
    if (poll_due) {
      co_await poll(polled->sensor);
      continue;
    }
    wake_.expires_at(polled ? due : now + std::chrono::hours(1));
    boost::system::error_code ec;
    co_await wake_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
}

// Holds the sensor: a reload may remove it, or add others, while its poll is on the wire.
asio::awaitable<void> BusScheduler::poll(std::shared_ptr<GatewaySensor> sensor) {
  {
    const BusyTime busy(stats_.busy);
    co_await sensor->driver->poll(line_);
  }
  ++stats_.polls;
  jobs_.polled();
  // Processed and published once the bus's next request is out: posted, this runs after the
  // handler going on from here has written that request (the write is where it first waits),
  // so the next transaction does not wait for the reading's tilt, alarms and snapshot.
  asio::post(wake_.get_executor(), [sensor] {
    process_new_reading(*sensor);
    sensor->publish();
  });
  Polled* polled = find_polled(sensor.get());
  if (polled == nullptr) co_return;  // removed meanwhile
  polled->schedule = after_poll(polled->schedule, sensor->driver->state().online,
                                sensor->config.poll, max_backoff, SteadyClock::now());
}

void BusScheduler::process_new_reading(GatewaySensor& sensor) {
  const SensorState& state = sensor.driver->state();
  if (state.sample_seq == sensor.processed_seq || !state.reading) return;
  sensor.processing.update(*state.reading);
  sensor.processed_seq = state.sample_seq;
}

template <class Result>
asio::awaitable<Result> BusScheduler::queue(BusWork work, SteadyClock::time_point deadline,
                                            std::uint64_t& expired) {
  // A retiring bus still carries out writes, those queued meanwhile too; nothing else.
  if (stopping_ || (retiring_ && !std::holds_alternative<SensorWrite>(work)))
    co_return std::get<Result>(refusal(work));
  const std::shared_ptr<BusJob> job = jobs_.push(std::move(work));
  wake_.cancel();
  if (!co_await jobs_.wait(job, deadline)) ++expired;
  co_return std::get<Result>(std::move(*job->answer));
}

asio::awaitable<WriteResult> BusScheduler::write(SensorWrite write,
                                                 SteadyClock::time_point deadline) {
  if (WriteResult admitted = write.admit(*this); !admitted) co_return admitted;
  BusWork work = std::move(write);  // named: g++ 12 destroys a temporary in co_await twice
  co_return co_await queue<WriteResult>(std::move(work), deadline, stats_.writes_expired);
}

asio::awaitable<ForwardResult> BusScheduler::forward(std::uint8_t slave,
                                                     std::vector<std::uint8_t> pdu,
                                                     SteadyClock::time_point deadline) {
  if (jobs_.queued_forwards() >= max_queued_forwards_) {
    ++stats_.forwards_busy;
    co_return Unexpected{ForwardFailure::busy};
  }
  BusWork work = ForwardRequest{slave, std::move(pdu)};  // named, as in write()
  co_return co_await queue<ForwardResult>(std::move(work), deadline, stats_.forwards_expired);
}

asio::awaitable<CommandExchangeResult> BusScheduler::exchange_for_command(
    LineRequest request, SteadyClock::time_point deadline) {
  BusWork work = CommandTransaction{std::move(request)};  // named, as in write()
  co_return co_await queue<CommandExchangeResult>(std::move(work), deadline,
                                                  stats_.command_exchanges_expired);
}

asio::awaitable<void> BusScheduler::carry_out(BusJob& job) {
  const BusyTime busy(stats_.busy);
  if (auto* write = std::get_if<SensorWrite>(&job.work))
    job.answer_with(co_await write->run(line_, *this, stats_.writes));
  else if (auto* forward = std::get_if<ForwardRequest>(&job.work))
    job.answer_with(co_await exchange(*forward));
  else
    job.answer_with(co_await transact(std::get<CommandTransaction>(job.work)));
}

asio::awaitable<ForwardResult> BusScheduler::exchange(const ForwardRequest& forward) {
  if (make_forward_ == nullptr) {
    ++stats_.forwards_unframed;
    co_return Unexpected{ForwardFailure::unframed};
  }
  auto made = make_forward_(forward.slave, forward.pdu);
  if (!made) {
    ++stats_.forwards_unframed;
    spdlog::warn("{}: request for slave {} not forwarded: {}", name_, forward.slave, made.error());
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
    spdlog::debug("{}: forwarded request to slave {}: {}", name_, forward.slave,
                  to_string(done.error()));
    co_return Unexpected{ForwardFailure::no_response};
  }
  auto reply = forwarded.reply_pdu();
  if (!reply) {
    ++stats_.forward_timeouts;
    spdlog::debug("{}: forwarded request to slave {}: {}", name_, forward.slave, reply.error());
    co_return Unexpected{ForwardFailure::no_response};
  }
  ++stats_.forwarded;
  co_return std::move(*reply);
}

asio::awaitable<CommandExchangeResult> BusScheduler::transact(
    const CommandTransaction& command) {
  CommandExchangeResult result;
  result.done = co_await line_.transact(command.request);
  result.timing = line_.last_timing();
  result.generation = line_.generation();
  ++stats_.command_exchanges;
  co_return result;
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

}  // namespace tiltgate
