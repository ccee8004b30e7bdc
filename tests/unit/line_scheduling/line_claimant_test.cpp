// LineClaimant and SharedLine together (line_scheduling/line_claimant.h, line_scheduling/shared_line.h), on a
// fake line (unit/support/fake_bus.h): an attempt that times out gives the line back before
// its retry, a claimant whose wait ran out never takes the line from the one holding it, and
// nothing is sent that could end after a deadline. One transaction on the line at a time,
// always.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <optional>
#include <string>
#include <vector>

#include "line_scheduling/line_claimant.h"
#include "line_scheduling/shared_line.h"
#include "unit/support/fake_bus.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;

namespace {

struct Bench {
  Bench() {
    line.on_attempt = [this](const LineRequest& request) {
      events.push_back("attempt " + std::to_string(request.bytes.at(0)));
    };
    line.silent = [this](const LineRequest& request) { return silent == request.bytes.at(0); };
    asio::co_spawn(io, shared.run(), asio::detached);
  }
  ~Bench() {
    shared.stop();
    io.restart();
    io.run_for(100ms);
  }

  // `claimant` takes its turn, sends one request {tag} held `hold` (retries as given), and
  // finishes; `done` holds what its transaction came to.
  void work(LineClaimant& claimant, std::uint8_t tag, std::chrono::milliseconds hold, int retries,
            std::optional<Expected<Done, LineError>>& done) {
    asio::co_spawn(
        io,
        [&claimant, tag, hold, retries, &done]() -> asio::awaitable<void> {
          if (co_await claimant.wait_turn() != TurnGrant::granted) co_return;
          LineRequest request;
          request.bytes = {tag};
          request.timeout = hold;
          request.retries = retries;
          done = co_await claimant.transact(request);
          claimant.finish();
        },
        asio::detached);
  }

  asio::io_context io;
  FakeLine line{io.get_executor()};
  SharedLine shared{io.get_executor(), line};
  BusEvents events;
  std::uint8_t silent = 0;  // the tag nobody answers
};

}  // namespace

TEST_CASE("line claimant: an attempt that times out gives the line back, and its retry waits its turn") {
  Bench bench;
  bench.silent = 1;
  LineClaimant failing(bench.shared, TurnKind::forward, nullptr, std::nullopt, 1);
  LineClaimant other(bench.shared, TurnKind::forward, nullptr, std::nullopt, 2);
  std::optional<Expected<Done, LineError>> failed, answered;
  bench.work(failing, 1, 20ms, 1, failed);
  bench.work(other, 2, 20ms, 0, answered);
  REQUIRE(run_until(bench.io, [&] { return failed && answered; }));
  CHECK(bench.events == BusEvents{"attempt 1", "attempt 2", "attempt 1"});
  REQUIRE_FALSE(failed->has_value());
  CHECK(failed->error() == LineError::timeout);
  CHECK(answered->has_value());
  CHECK(bench.line.most_at_once == 1);
}

TEST_CASE("line claimant: one whose wait for its retry ran out never takes the line from the one holding it") {
  Bench bench;
  bench.silent = 1;
  // A write with 100 ms to go: its first attempt times out at 40 ms, and its retry cannot end
  // in time while the poll below holds the line.
  LineClaimant write(bench.shared, TurnKind::write, nullptr, SteadyClock::now() + 100ms);
  LineClaimant poll(bench.shared, TurnKind::poll, nullptr, std::nullopt);
  LineClaimant forward(bench.shared, TurnKind::forward, nullptr, std::nullopt, 3);
  std::optional<Expected<Done, LineError>> wrote, polled, forwarded;
  asio::co_spawn(
      bench.io,
      [&]() -> asio::awaitable<void> {
        REQUIRE(co_await write.wait_turn() == TurnGrant::granted);
        LineRequest request;
        request.bytes = {1};
        request.timeout = 40ms;
        request.retries = 1;
        wrote = co_await write.transact(request);
        // A driver's next step (a re-lock) after the failed one: refused too, sent never.
        request.retries = 0;
        const auto again = co_await write.transact(request);
        CHECK_FALSE(again.has_value());
        write.finish();
      },
      asio::detached);
  bench.work(poll, 2, 200ms, 0, polled);
  bench.work(forward, 3, 10ms, 0, forwarded);
  REQUIRE(run_until(bench.io, [&] { return wrote && polled && forwarded; }));
  REQUIRE_FALSE(wrote->has_value());
  CHECK(wrote->error() == LineError::expired);
  CHECK(bench.events == BusEvents{"attempt 1", "attempt 2", "attempt 3"});
  CHECK(bench.line.most_at_once == 1);
}

TEST_CASE("line claimant: nothing is sent that could end after the deadline") {
  Bench bench;
  LineClaimant late(bench.shared, TurnKind::write, nullptr, SteadyClock::now() + 50ms);
  std::optional<Expected<Done, LineError>> done;
  bench.work(late, 1, 80ms, 0, done);  // the line would hold it 80 ms
  REQUIRE(run_until(bench.io, [&] { return done.has_value(); }));
  REQUIRE_FALSE(done->has_value());
  CHECK(done->error() == LineError::expired);
  CHECK(bench.events.empty());
}
