// A fake serial line and a fake sensor driver for testing the gateway core (BusScheduler,
// RequestRouter) on an io_context without a tty or a protocol. The driver records what the
// core asked of it, in one event list shared by every sensor of a bus, so tests can assert on
// order and counts rather than on time.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <algorithm>
#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "driver/line.h"
#include "driver/sensor_driver.h"
#include "line_scheduling/gateway_sensor.h"
#include "mapping/default_maps.h"

namespace tiltgate::test {

// Every transaction holds the line for its request's `timeout` (zero: just yields to the
// event loop), then succeeds; with `reply` set, the request's framer is fed what it returns
// and the transaction times out unless the framer takes it as a whole reply; one that `silent`
// says nobody answers times out. A request leaving its retries to the line gets `retries`.
// Counts attempts, tells `on_attempt` of each as it starts, and keeps the most that were ever
// on the line at once (one, unless the bus let two talk over each other).
class FakeLine : public Line {
 public:
  explicit FakeLine(boost::asio::any_io_executor executor) : executor_(executor) {}

  boost::asio::awaitable<Expected<Done, LineError>> transact(LineRequest request) override {
    ++stats_.attempts;
    if (on_attempt) on_attempt(request);
    if (!open) co_return Unexpected{LineError::closed};
    most_at_once = std::max(most_at_once, ++on_the_line_);
    boost::asio::steady_timer busy(executor_, request.timeout);
    co_await busy.async_wait(boost::asio::use_awaitable);
    --on_the_line_;
    if (silent && silent(request)) co_return Unexpected{LineError::timeout};
    if (!reply || request.framer == nullptr) co_return Done{};
    request.framer->reset();
    const std::vector<std::uint8_t> bytes = reply(request);
    // As SerialLine asks: a framer that asks someone else is awaited.
    bool whole = false;
    if (request.framer->asks_asynchronously())
      whole = co_await request.framer->feed_async(bytes);
    else
      whole = request.framer->feed(bytes);
    if (!whole) co_return Unexpected{LineError::timeout};
    co_return Done{};
  }

  std::function<std::vector<std::uint8_t>(const LineRequest&)> reply;
  std::function<bool(const LineRequest&)> silent;
  std::function<void(const LineRequest&)> on_attempt;
  bool open = true;
  int retries_left_to_the_line = 0;
  int most_at_once = 0;
  std::uint64_t generation() const override { return 1; }
  bool is_open() const override { return open; }
  int retries() const override { return retries_left_to_the_line; }
  const std::string& name() const override { return name_; }
  const LineStats& stats() const override { return stats_; }
  const LineTiming& last_timing() const override { return timing_; }

 private:
  boost::asio::any_io_executor executor_;
  int on_the_line_ = 0;
  std::string name_ = "fake";
  LineStats stats_;
  LineTiming timing_;
};

// Events as "<sensor> poll", "<sensor> poll end", "<sensor> write", "<sensor> write end".
using BusEvents = std::vector<std::string>;

// An H6 as the core sees it. Each poll and write is one line transaction of poll_time /
// write_time, its request the sensor's address, with the line's retries; a poll brings a
// reading while `answers` and the line answered, else the sensor goes offline (a time-out is
// counted, as drivers count them). A write fails as no response when the line did not answer.
// A bus_address write moves the sensor, as the real drivers do.
class FakeDriver : public SensorDriver {
 public:
  FakeDriver(std::string name, std::uint32_t address, BusEvents& events)
      : name_(std::move(name)), events_(events) {
    state_.bus_address = address;
  }

  bool answers = true;
  std::chrono::milliseconds poll_time{0};
  std::chrono::milliseconds write_time{0};
  // Transactions of each write, all sent whatever became of those before (as a Rieker write
  // still sends its re-lock after a failed setting); the write reports the first failure.
  int write_exchanges = 1;
  std::function<void()> on_poll;  // runs as each poll starts, before it takes the line
  // Each reading's angles: x = y = the poll's number (else 1.0 and 2.0), so a reply that mixes
  // two readings shows.
  bool counting = false;
  int polls = 0;
  mutable int checks = 0;  // check_write calls
  std::vector<std::pair<WriteTarget, double>> writes;  // every write that reached the driver

  std::string_view model() const override { return "h6"; }
  void follow_address(std::uint32_t address) override { state_.bus_address = address; }
  WriteResult check_write(WriteTarget, double) const override {
    ++checks;
    return Done{};
  }
  boost::asio::awaitable<void> poll(Line& line) override {
    ++polls;
    events_.push_back(name_ + " poll");
    if (on_poll) on_poll();
    const auto sent = co_await line.transact(request(poll_time));
    state_.online = answers && sent.has_value();
    state_.unanswered = !state_.online && (sent || sent.error() == LineError::timeout);
    if (state_.unanswered) ++state_.counters.timeouts;
    if (state_.online) {
      const double x = counting ? polls : 1.0;
      state_.reading = Reading{x, counting ? x : 2.0, {}, {}, {}, SteadyClock::now(), {}};
      ++state_.sample_seq;
    }
    events_.push_back(name_ + " poll end");
  }
  boost::asio::awaitable<WriteResult> write(Line& line, WriteTarget target,
                                            double value) override {
    events_.push_back(name_ + " write");
    writes.emplace_back(target, value);
    std::optional<LineError> failed;
    for (int i = 0; i < write_exchanges; ++i) {
      const auto sent = co_await line.transact(request(write_time));
      if (!sent && !failed) failed = sent.error();
    }
    if (failed) {
      events_.push_back(name_ + " write failed");
      co_return Unexpected{WriteError{WriteErrorKind::no_response, to_string(*failed)}};
    }
    if (target == WriteTarget::bus_address) state_.bus_address = std::uint32_t(value);
    events_.push_back(name_ + " write end");
    co_return Done{};
  }
  const SensorState& state() const override {
    if (on_state) on_state();
    return state_;
  }
  void reset_counters() override { state_.counters = {}; }
  // Runs at each state() call: a test's way to make the core's reading of a sensor fail.
  std::function<void()> on_state;

 private:
  LineRequest request(std::chrono::milliseconds hold) const {
    LineRequest request;
    request.bytes = {std::uint8_t(state_.bus_address)};
    request.timeout = hold;
    return request;
  }

  std::string name_;
  BusEvents& events_;
  SensorState state_;
};

// A configured sensor around a FakeDriver, with the built-in H6 map (holding 0 filter,
// 7 bus_address).
inline std::unique_ptr<GatewaySensor> fake_sensor(std::string name, std::uint8_t unit_id,
                                                  std::uint32_t address, BusEvents& events,
                                                  std::chrono::milliseconds poll =
                                                      std::chrono::milliseconds(100)) {
  auto sensor = std::make_unique<GatewaySensor>();
  sensor->config.name = name;
  sensor->config.bus = "bus";
  sensor->config.model = "h6";
  sensor->config.address = address;
  sensor->config.unit_id = unit_id;
  sensor->config.poll = poll;
  sensor->driver = std::make_unique<FakeDriver>(std::move(name), address, events);
  sensor->map = default_map(registered_families(), "h6");
  sensor->written.assign(sensor->map.holding_end(), 0);
  return sensor;
}

inline FakeDriver& fake_driver(GatewaySensor& sensor) {
  return static_cast<FakeDriver&>(*sensor.driver);
}

// A bus made by a test, lent where the gateway would hand out a shared one
// (RequestRouter::pass_through(), ControlServer's buses): the pointer keeps nothing alive.
template <class Bus>
std::shared_ptr<Bus> lent(Bus& bus) {
  return std::shared_ptr<Bus>(std::shared_ptr<Bus>(), &bus);
}

// Runs the io_context until `done()` holds or `limit` passes; false on the limit.
inline bool run_until(boost::asio::io_context& io, const std::function<bool()>& done,
                      std::chrono::seconds limit = std::chrono::seconds(20)) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    io.restart();
    io.run_one_for(std::chrono::milliseconds(50));
  }
  return true;
}

}  // namespace tiltgate::test
