#include "line_scheduling/bus_scheduler.h"

#include <algorithm>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <exception>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "audit/audit_trail.h"
#include "driver/visible_text.h"
#include "line_scheduling/exception_text.h"

namespace tiltgate {

namespace asio = boost::asio;

BusScheduler::BusScheduler(asio::any_io_executor executor, Line& line, std::string name)
    : line_(executor, line, name), name_(std::move(name)) {
  line_.on_held = [this](const GatewaySensor& sensor, SteadyClock::time_point now) {
    log_held(sensor, now);
  };
}

BusScheduler::~BusScheduler() { stop(); }

void BusScheduler::add(GatewaySensor& sensor) {
  // An empty owner: a pointer that keeps nothing alive.
  add(std::shared_ptr<GatewaySensor>(std::shared_ptr<GatewaySensor>(), &sensor));
}

void BusScheduler::add(std::shared_ptr<GatewaySensor> sensor) {
  // The gateway gives it an owning pointer first; a bus made on its own (tests) lends itself.
  if (!sensor->bus) sensor->bus = std::shared_ptr<BusScheduler>(std::shared_ptr<BusScheduler>(), this);
  // The sensor arrives configured: its mounting and alarms are known from here on.
  sensor->processing = SensorProcessing(sensor->config.mounting, sensor->config.alarms,
                                        sensor->config.lever_m, sensor->baseline);
  sensor->processed_seq = sensor->driver->state().sample_seq;
  sensor->publish();
  auto polled = std::make_shared<Polled>();
  polled->sensor = std::move(sensor);
  polled->schedule = PollSchedule{SteadyClock::now()};
  sensors_.push_back(polled);
  if (line_.stopped() || retiring_) return;
  asio::co_spawn(executor(), keep_polling(polled),
                 [bus = name_, sensor = polled->sensor->config.name](std::exception_ptr e) {
                   if (e)
                     spdlog::error("{}: polling of sensor \"{}\" ended: {}", bus, sensor,
                                   exception_text(e));
                 });
}

void BusScheduler::remove(const GatewaySensor& sensor) {
  std::erase_if(sensors_, [&](const std::shared_ptr<Polled>& polled) {
    if (polled->sensor.get() != &sensor) return false;
    polled->removed = true;
    // A poll on the wire finishes first; a poller waiting for its turn ends now.
    if (polled->poller != nullptr && polled->poller->waiting()) line_.refuse(*polled->poller);
    return true;
  });
}

void BusScheduler::retire() {
  retiring_ = true;
  for (const auto& polled : std::vector(sensors_)) remove(*polled->sensor);
  line_.keep_only_writes();
}

void BusScheduler::stop() {
  for (const auto& polled : sensors_) polled->removed = true;
  // Its sensors hold it (GatewaySensor::bus): let them go, or neither is ever freed.
  sensors_.clear();
  line_.stop();
}

asio::awaitable<void> BusScheduler::run() { co_await line_.run(); }

BusSchedulerStats BusScheduler::stats() const {
  BusSchedulerStats stats = stats_;
  stats.busy = line_.busy();
  stats.restarts = line_.restarts() + stats_.poll_failures;
  return stats;
}

void BusScheduler::log_held(const GatewaySensor& sensor, SteadyClock::time_point now) {
  const auto polled = std::find_if(sensors_.begin(), sensors_.end(), [&](const auto& p) {
    return p->sensor.get() == &sensor;
  });
  if (polled == sensors_.end()) return;
  Polled& p = **polled;
  if (p.held_logged && now - *p.held_logged < kHeldLogInterval) return;
  // Held again within two intervals: the same episode, logged with its share since the last
  // line; else a new one.
  const bool goes_on = p.held_logged && now - *p.held_logged < 2 * kHeldLogInterval;
  if (goes_on) {
    const std::chrono::duration<double> over = now - *p.held_logged;
    const std::chrono::duration<double> took = sensor.line_time - p.line_time_logged;
    spdlog::warn("{}: sensor \"{}\" still failing, held to one turn between rounds: it had "
                 "{:.0f} % of the line's time over the last {:.0f} s",
                 name_, sensor.config.name, 100 * std::min(took / over, 1.0), over.count());
  } else {
    spdlog::warn("{}: sensor \"{}\" is failing: its attempts take one turn each between rounds "
                 "of the other sensors' polls, so they stay fresh (its share of the line: "
                 "line_share in /api/sensors)",
                 name_, sensor.config.name);
  }
  p.held_logged = now;
  p.line_time_logged = sensor.line_time;
}

// The sensors' pollers.

SteadyClock::time_point BusScheduler::due_of(const Polled& polled) {
  return polled.held_until ? std::max(polled.schedule.due, *polled.held_until)
                           : polled.schedule.due;
}

asio::awaitable<void> BusScheduler::keep_polling(std::shared_ptr<Polled> polled) {
  LineClaimant line(line_, TurnKind::poll, polled->sensor.get(), std::nullopt);
  polled->poller = &line;
  while (!polled->removed) {
    if (heard_ != nullptr) {
      co_await listen(*polled);
      continue;
    }
    if (co_await line.wait_turn(due_of(*polled)) != TurnGrant::granted) break;
    if (heard_ != nullptr) {  // the bus began listening while it waited: nothing is sent
      line.finish();
      continue;
    }
    std::exception_ptr failure;
    try {
      co_await poll(*polled, line);
    } catch (...) {
      failure = std::current_exception();
    }
    if (failure) poll_failed(*polled, line, failure);
  }
  polled->poller = nullptr;
}

// A poll that threw (a driver's bug, memory): the poller goes on, the sensor polled again
// after kPollFailurePause, so one bad reply or driver path never ends a sensor's polling for
// good; logged at error at most once a minute per sensor, counted.
void BusScheduler::poll_failed(Polled& polled, LineClaimant& line, std::exception_ptr failure) {
  line.finish();  // the line goes on to the others
  ++stats_.poll_failures;
  ++polled.failures;
  const auto now = SteadyClock::now();
  polled.schedule.due = now + kPollFailurePause;
  if (polled.failure_logged && now - *polled.failure_logged < kHeldLogInterval) return;
  polled.failure_logged = now;
  spdlog::error("{}: polling sensor \"{}\" failed: {}; polled again in {} s ({} failure(s) so "
                "far: tiltgate_bus_restarts_total)",
                name_, polled.sensor->config.name, exception_text(failure),
                kPollFailurePause.count(),
                polled.failures);
}

// Holds the sensor: a reload may remove it, or add others, while its poll is on the wire.
asio::awaitable<void> BusScheduler::poll(Polled& polled, LineClaimant& line) {
  const std::shared_ptr<GatewaySensor> sensor = polled.sensor;
  co_await sensor->driver->poll(line);
  ++stats_.polls;
  line.finish();  // the next turn is given now
  // Processed and published once the next turn's request is out: posted after that turn's
  // claimant was woken, this runs after it has written its request (where it first waits),
  // so the next transaction does not wait for the reading's tilt, alarms and snapshot.
  // `this` lives as long as the sensor, which holds its bus (GatewaySensor::bus).
  asio::post(executor(), [this, sensor] {
    process_new_reading(*sensor);
    sensor->publish();
  });
  // A poll that found the tty gone says nothing of the sensor: it is polled at its period,
  // so it reads fresh at the first poll after the tty is back.
  const bool answered = sensor->driver->state().online || !line_.line().is_open();
  const auto now = SteadyClock::now();
  if (polled.burst_until && now >= *polled.burst_until) polled.burst_until.reset();
  polled.schedule = after_poll(polled.schedule, answered, sensor->config.poll, max_backoff, now);
  // In a burst: due again as this poll ends, or at its period's time when that is earlier (a
  // full line runs behind: there it keeps at least its share). The line's turns, earliest due
  // first, put the neighbours already due before it. A sensor that stops answering backs off
  // from its poll_ms as ever: a burst never hammers a silent line.
  if (polled.burst_until && answered) polled.schedule.due = std::min(polled.schedule.due, now);
}

bool BusScheduler::burst(const GatewaySensor& sensor, SteadyClock::time_point until) {
  for (const auto& polled : sensors_) {
    if (polled->sensor.get() != &sensor) continue;
    if (!polled->burst_until || *polled->burst_until < until) polled->burst_until = until;
    // Due now: its poller, waiting for its next period, takes the line's next turn.
    polled->schedule.due = std::min(polled->schedule.due, SteadyClock::now());
    reschedule(*polled);
    return true;
  }
  return false;
}

void BusScheduler::listen_to(HeardSource* heard) {
  heard_ = heard;
  for (const auto& polled : sensors_) {
    polled->sensor->standby = heard != nullptr;
    polled->sensor->publish();
  }
}

asio::awaitable<void> BusScheduler::listen(Polled& polled) {
  HeardSource* heard = heard_;
  if (polled.heard_from != heard || !polled.heard_line) {
    polled.heard_line = heard->line_for_poller();
    polled.heard_from = heard;
  }
  const std::shared_ptr<GatewaySensor> sensor = polled.sensor;
  sensor->standby = true;
  std::exception_ptr failure;
  try {
    co_await sensor->driver->poll(*polled.heard_line);
    ++stats_.polls;
  } catch (...) {
    failure = std::current_exception();
  }
  process_new_reading(*sensor);
  sensor->publish();
  if (failure) {
    ++stats_.poll_failures;
    spdlog::error("{}: reading sensor \"{}\" from what was heard failed: {}", name_,
                  sensor->config.name, exception_text(failure));
    asio::steady_timer pause(executor(), kPollFailurePause);
    boost::system::error_code ignored;
    co_await pause.async_wait(asio::redirect_error(asio::use_awaitable, ignored));
    co_return;
  }
  if (heard_ == heard) co_await heard->pace(*polled.heard_line);
  if (heard_ != heard) {
    polled.heard_line.reset();  // the line taken, or another source: start afresh
    polled.heard_from = nullptr;
    sensor->standby = heard_ != nullptr;
  }
}

void BusScheduler::process_new_reading(GatewaySensor& sensor) const {
  const SensorState& state = sensor.driver->state();
  if (state.sample_seq == sensor.processed_seq || !state.reading) return;
  const Reading& reading = *state.reading;
  // The reply's time on the wall clock: now, less how long ago it arrived by the steady clock.
  const auto ago = SteadyClock::now() - reading.taken;
  const std::int64_t unix_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
      (std::chrono::system_clock::now() - ago).time_since_epoch()).count();
  const bool synchronised = clock_synchronised_ ? clock_synchronised_() : true;
  sensor.processing.update(reading, unix_ms, synchronised);
  sensor.processed_seq = state.sample_seq;
  const DerivedState& d = sensor.processing.derived();
  sensor.feed->put(FedSample{unix_ms, reading.taken, synchronised, d.angle_x, d.angle_y, d.tilt,
                             d.relative_x, d.relative_y, d.displacement_mm,
                             reading.temperature_c.value_or(NAN), d.alarms,
                             d.alarms_danger},
                   sensor.processing.changed());
}

void BusScheduler::reschedule(Polled& polled) {
  LineClaimant* poller = polled.poller;
  // Mid-way through a poll, it takes its due time when it next waits.
  if (poller != nullptr && poller->waiting() && !poller->between_attempts())
    line_.reschedule(*poller, due_of(polled));
}

bool BusScheduler::not_answering(const GatewaySensor& sensor) const {
  if (known_offline(sensor.driver->state())) return true;
  for (const auto& polled : sensors_)
    if (polled->sensor.get() == &sensor)
      return polled->poller != nullptr && polled->poller->retrying();
  return false;
}

BusScheduler::Polled* BusScheduler::find_polled(std::uint32_t address) {
  for (const auto& polled : sensors_)
    if (polled->sensor->driver->state().bus_address == address) return polled.get();
  return nullptr;
}

// Writes, forwarded requests, commands.

WriteResult BusScheduler::check_address_free(const GatewaySensor& sensor, WriteTarget target,
                                             double value) const {
  const auto address = sensor.driver->address_after(target, value);
  if (!address) return Done{};
  for (const auto& other : sensors_) {
    // Drivers follow their sensor to a new address, so this is where each one answers now.
    if (other->sensor.get() == &sensor ||
        other->sensor->driver->state().bus_address != *address)
      continue;
    return Unexpected{WriteError{
        WriteErrorKind::bad_value,
        fmt::format("address {} is taken by sensor \"{}\" on bus \"{}\"", *address,
                    other->sensor->config.name, name_)}};
  }
  return Done{};
}

asio::awaitable<WriteResult> BusScheduler::write(SensorWrite write,
                                                 SteadyClock::time_point deadline) {
  if (WriteResult admitted = write.admit(*this); !admitted) co_return admitted;
  if (heard_ != nullptr) {
    WriteError standby{WriteErrorKind::device_exception,
                       "this gateway is the standby of a redundant pair: write through the "
                       "active one"};
    standby.device_exception = 0x0A;  // gateway path unavailable: this path sends nothing
    co_return write.fail(*this, std::move(standby));
  }
  const WriteError unanswered{WriteErrorKind::no_response, "sensor not answering: not sent"};
  if (line_.stopped())
    co_return write.fail(*this, {WriteErrorKind::no_response, "gateway stopping"});
  // Known offline, or its poll is between retries after its sensor did not answer: the
  // write's own retries would only hold the line and the answer (its probes find it when it
  // is back).
  if (not_answering(write.sensor())) {
    ++stats_.writes_offline;
    co_return write.fail(*this, unanswered);
  }
  LineClaimant line(line_, TurnKind::write, &write.sensor(), deadline);
  const TurnGrant grant = co_await line.wait_turn();
  if (grant == TurnGrant::refused)
    co_return write.fail(*this, {WriteErrorKind::no_response, "gateway stopping"});
  if (grant == TurnGrant::expired) {
    ++stats_.writes_expired;
    co_return write.fail(*this,
                         {WriteErrorKind::busy, "bus too busy: write not started in time"});
  }
  // Its poll may have found it offline while the write waited.
  if (not_answering(write.sensor())) {
    line.finish();
    ++stats_.writes_offline;
    co_return write.fail(*this, unanswered);
  }
  WriteResult result = co_await write.run(line, *this, stats_.writes);
  line.finish();
  co_return result;
}

void BusScheduler::enable_forwarding(ForwardFactory make, std::size_t max_queued) {
  make_forward_ = make;
  max_queued_forwards_ = max_queued;
}

bool BusScheduler::forward_admitted(std::uint64_t client) const {
  const SharedLine::ForwardsWaiting waiting = line_.forwards_waiting(client);
  // Full: each client is held to its share, so a new one still gets in.
  return waiting.queued < max_queued_forwards_ ||
         waiting.from_client < max_queued_forwards_ / waiting.clients;
}

asio::awaitable<ForwardResult> BusScheduler::forward(std::uint8_t slave,
                                                     std::vector<std::uint8_t> pdu,
                                                     SteadyClock::time_point deadline,
                                                     std::uint64_t client) {
  if (line_.stopped() || retiring_) co_return Unexpected{ForwardFailure::no_response};
  if (heard_ != nullptr) co_return Unexpected{ForwardFailure::standby};
  if (!forward_admitted(client)) {
    ++stats_.forwards_busy;
    co_return Unexpected{ForwardFailure::busy};
  }
  LineClaimant line(line_, TurnKind::forward, nullptr, deadline, client);
  const TurnGrant grant = co_await line.wait_turn();
  if (grant == TurnGrant::refused) co_return Unexpected{ForwardFailure::no_response};
  if (grant == TurnGrant::expired) {
    ++stats_.forwards_expired;
    co_return Unexpected{ForwardFailure::expired};
  }
  ForwardResult result = co_await exchange(line, slave, pdu);
  line.finish();
  co_return result;
}

asio::awaitable<ForwardResult> BusScheduler::exchange(LineClaimant& line, std::uint8_t slave,
                                                      const std::vector<std::uint8_t>& pdu) {
  if (make_forward_ == nullptr) {
    ++stats_.forwards_unframed;
    co_return Unexpected{ForwardFailure::unframed};
  }
  auto made = make_forward_(slave, pdu);
  if (!made) {
    ++stats_.forwards_unframed;
    spdlog::warn("{}: request for slave {} not forwarded: {}", name_, slave, made.error());
    co_return Unexpected{ForwardFailure::unframed};
  }
  ForwardedExchange& forwarded = **made;
  LineRequest request;
  request.bytes = forwarded.request_bytes();
  request.framer = &forwarded.framer();
  request.timeout = std::chrono::milliseconds(0);  // the bus's reply time-out
  request.retries = 0;  // the client retries; a forwarded write must never run twice
  auto done = co_await line.transact(std::move(request));
  if (!done) {
    ++stats_.forward_timeouts;
    spdlog::debug("{}: forwarded request to slave {}: {}", name_, slave, to_string(done.error()));
    co_return Unexpected{ForwardFailure::no_response};
  }
  auto reply = forwarded.reply_pdu();
  if (!reply) {
    ++stats_.forward_timeouts;
    spdlog::debug("{}: forwarded request to slave {}: {}", name_, slave, reply.error());
    co_return Unexpected{ForwardFailure::no_response};
  }
  ++stats_.forwarded;
  co_return std::move(*reply);
}

asio::awaitable<CommandExchangeResult> BusScheduler::exchange_for_command(
    LineRequest request, SteadyClock::time_point deadline) {
  CommandExchangeResult result;
  result.done = Unexpected{LineError::cancelled};
  if (line_.stopped() || retiring_) co_return result;
  if (heard_ != nullptr) {  // a standby sends nothing, a command's transaction included
    result.done = Unexpected{LineError::closed};
    co_return result;
  }
  LineClaimant line(line_, TurnKind::command, nullptr, deadline);
  const TurnGrant grant = co_await line.wait_turn();
  if (grant == TurnGrant::refused) co_return result;
  if (grant == TurnGrant::expired) {
    ++stats_.command_exchanges_expired;
    result.done = Unexpected{LineError::timeout};
    result.expired = true;
    co_return result;
  }
  result.done = co_await line.transact(std::move(request));
  result.timing = line.last_timing();
  result.generation = line_.line().generation();
  ++stats_.command_exchanges;
  line.finish();
  co_return result;
}

// Commissioning commands moving a sensor.

std::optional<std::string> BusScheduler::follow_address(std::uint32_t from, std::uint32_t to,
                                                        const WriteOrigin& by) {
  Polled* polled = find_polled(from);
  record_command(by, polled ? polled->sensor.get() : nullptr, from, "address",
                 std::to_string(from), std::to_string(to), "ack");
  if (polled == nullptr) return std::nullopt;
  polled->sensor->driver->follow_address(to);
  polled->sensor->publish();
  // Poll it at its new address at once: the command's read-back and the PLC agree sooner.
  polled->schedule = PollSchedule{SteadyClock::now()};
  polled->held_until.reset();
  reschedule(*polled);
  spdlog::info("{}: sensor \"{}\" moved from address {} to {} by a commissioning command of {}",
               name_, polled->sensor->config.name, from, to, visible_text(by.who));
  return polled->sensor->config.name;
}

std::optional<std::string> BusScheduler::note_setting(std::uint32_t address, WriteTarget setting,
                                                      double value, const std::string& result,
                                                      const WriteOrigin& by) {
  Polled* polled = find_polled(address);
  // As a follow records a move: "address".
  std::string name = setting == WriteTarget::bus_address ? "address"
                                                         : fmt::format("setting {}", setting.id);
  if (polled != nullptr && polled->sensor->model != nullptr && setting != WriteTarget::bus_address)
    for (const SettingDescriptor& known : polled->sensor->model->settings)
      if (known.id == setting) name = known.name;
  std::string old_value;
  if (polled != nullptr)
    if (auto known = polled->sensor->driver->state().settings.get(setting))
      old_value = fmt::format("{}", *known);
  record_command(by, polled ? polled->sensor.get() : nullptr, address, name,
                 std::move(old_value), fmt::format("{}", value), result);
  if (polled == nullptr) return std::nullopt;
  GatewaySensor& sensor = *polled->sensor;
  if (result != "ack") return sensor.config.name;
  sensor.driver->note_acknowledged(setting, value);
  sensor.publish();
  spdlog::info("{}: sensor \"{}\": {} = {} set by a commissioning command of {}", name_,
               sensor.config.name, visible_text(name), value, visible_text(by.who));
  return sensor.config.name;
}

void BusScheduler::note_carried(std::optional<std::uint32_t> address, std::string function,
                                std::string data, std::string result, std::int64_t unix_ms,
                                const WriteOrigin& by) {
  if (address) {
    const Polled* polled = find_polled(*address);
    record_command(by, polled ? polled->sensor.get() : nullptr, *address, std::move(function), "",
                   std::move(data), std::move(result), unix_ms);
  } else if (audit_ != nullptr) {  // the bus's, the device not known
    audit_->record({unix_ms, by, name_, std::move(function), "", std::move(data),
                    std::move(result)});
  }
}

void BusScheduler::record_command(const WriteOrigin& by, const GatewaySensor* sensor,
                                  std::uint32_t address, std::string setting,
                                  std::string old_value, std::string new_value,
                                  std::string result, std::int64_t unix_ms) const {
  if (audit_ == nullptr) return;
  AuditRecord record;
  record.unix_ms = unix_ms;
  record.origin = by;
  record.sensor = name_ + "/" + (sensor ? sensor->config.name : std::to_string(address));
  record.setting = std::move(setting);
  record.old_value = std::move(old_value);
  record.new_value = std::move(new_value);
  record.result = std::move(result);
  audit_->record(std::move(record));
}

std::optional<std::string> BusScheduler::hold(std::uint32_t address,
                                              SteadyClock::time_point until) {
  Polled* polled = find_polled(address);
  if (polled == nullptr) return std::nullopt;
  polled->held_until = until;
  reschedule(*polled);
  return polled->sensor->config.name;
}

void BusScheduler::release(std::uint32_t address) {
  for (const auto& polled : sensors_)
    if (polled->held_until && polled->sensor->driver->state().bus_address == address) {
      polled->held_until.reset();
      reschedule(*polled);
    }
}

}  // namespace tiltgate
