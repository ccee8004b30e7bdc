// The poll cycle's verdict on a sensor (driver/polled_sensor_driver.h) when the line could not
// tell whether it answered: a machine that held the reply back (LineError::overloaded) blames
// nobody, while a time-out still takes the sensor offline. And the slowest reply it keeps.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <deque>
#include <string>

#include "driver/polled_sensor_driver.h"

using namespace tiltgate;

namespace {

// A line whose transactions end as the test says, in order (then: answered).
class ScriptedLine final : public Line {
 public:
  boost::asio::awaitable<Expected<Done, LineError>> transact(LineRequest) override {
    if (outcomes.empty()) co_return Done{};
    const LineError outcome = outcomes.front();
    outcomes.pop_front();
    co_return Unexpected(outcome);
  }
  std::uint64_t generation() const override { return 1; }
  bool is_open() const override { return true; }
  int retries() const override { return 0; }
  const std::string& name() const override { return name_; }
  const LineStats& stats() const override { return stats_; }
  const LineTiming& last_timing() const override { return timing_; }

  std::deque<LineError> outcomes;
  LineTiming timing_;  // what every transaction reports

 private:
  std::string name_ = "line1";
  LineStats stats_;
};

// Identity and measurement, one transaction each.
class OneRequestDriver final : public PolledSensorDriver {
 public:
  OneRequestDriver() : PolledSensorDriver(ReplyTimeouts{}) {}
  std::string_view model() const override { return "test"; }
  WriteResult check_write(WriteTarget, double) const override { return Done{}; }
  void follow_address(std::uint32_t) override {}
  boost::asio::awaitable<WriteResult> write(Line&, WriteTarget, double) override {
    co_return Done{};
  }

 protected:
  boost::asio::awaitable<bool> read_identity(Line& line) override {
    const auto sent = co_await transact_counted(line, LineRequest{}, ExchangeOptions{});
    if (sent) state_.identity_known = true;
    identity_read_on(line.generation());
    co_return sent.has_value();
  }
  boost::asio::awaitable<void> read_measurement(Line& line) override {
    const auto sent = co_await transact_counted(line, LineRequest{}, ExchangeOptions{});
    if (sent) {
      state_.reading = Reading{};
      ++state_.counters.polls_ok;
    } else {
      ++state_.counters.polls_failed;
    }
  }
  const std::string& log_name() const override { return name_; }
  const char* kind() const override { return "sensor"; }

 private:
  std::string name_ = "boom";
};

void poll(OneRequestDriver& driver, Line& line) {
  boost::asio::io_context io;
  boost::asio::co_spawn(io, driver.poll(line), boost::asio::detached);
  io.run();
}

}  // namespace

TEST_CASE("a reply the machine held back (overloaded) leaves an online sensor online") {
  ScriptedLine line;
  OneRequestDriver driver;
  poll(driver, line);
  REQUIRE(driver.state().online);
  line.outcomes = {LineError::overloaded};
  poll(driver, line);
  CHECK(driver.state().online);
  CHECK_FALSE(driver.state().unanswered);
  CHECK(driver.state().counters.timeouts == 0);
  CHECK(driver.state().counters.polls_failed == 1);  // no reading, all the same
  // A time-out is the sensor's: offline.
  line.outcomes = {LineError::timeout};
  poll(driver, line);
  CHECK_FALSE(driver.state().online);
  CHECK(driver.state().counters.timeouts == 1);
}

TEST_CASE("the slowest reply is kept as the line waited for it, the machine's hold included") {
  ScriptedLine line;
  OneRequestDriver driver;
  line.timing_.reply_delay = std::chrono::milliseconds{3};
  poll(driver, line);
  CHECK(driver.state().counters.slowest_reply == std::chrono::milliseconds{3});
  line.timing_.machine_held = std::chrono::milliseconds{5};
  poll(driver, line);
  CHECK(driver.state().counters.slowest_reply == std::chrono::milliseconds{8});
  line.timing_ = LineTiming{};
  line.timing_.reply_delay = std::chrono::milliseconds{2};
  poll(driver, line);
  CHECK(driver.state().counters.slowest_reply == std::chrono::milliseconds{8});
  // Two transactions a poll (identity once, then measurements): 3 ms twice, 8 ms, 2 ms.
  const auto& buckets = driver.state().counters.reply_buckets;
  CHECK(buckets[1] == 1);  // within 2 ms
  CHECK(buckets[2] == 2);  // within 5 ms
  CHECK(buckets[3] == 1);  // within 10 ms
  CHECK(driver.state().counters.reply_ms_sum == 3 + 3 + 8 + 2);
}
