// The clock's state as every thread asks it (clock/clock_watch.h), through an injected reader
// and steady clock: read at most once a second, shared by threads, its changes logged once.
#include <doctest/doctest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "clock/clock_watch.h"
#include "sim/support/captured_log.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

ClockState synchronised(double error_ms) {
  ClockState state;
  state.synchronised = true;
  state.error_ms = error_ms;
  state.problem = ClockProblem::none;
  return state;
}

ClockState unsynchronised() {
  ClockState state;
  state.problem = ClockProblem::unbounded;
  return state;
}

// A reader that returns `next` and counts its calls; a steady clock the test moves.
struct FakeKernel {
  std::atomic<int> reads = 0;
  ClockState next = synchronised(5.0);
  std::chrono::steady_clock::time_point now = std::chrono::steady_clock::time_point{} + 1h;

  ClockReader reader() {
    return [this] {
      ++reads;
      return next;
    };
  }
  ClockWatch::SteadyNow clock() {
    return [this] { return now; };
  }
};

}  // namespace

TEST_CASE("clock watch: reads once when made, then at most once a second") {
  FakeKernel kernel;
  ClockWatch watch(kernel.reader(), kernel.clock());
  CHECK(kernel.reads == 1);
  CHECK(watch.current() == synchronised(5.0));
  kernel.next = synchronised(5.5);
  kernel.now += 999ms;
  CHECK(watch.current() == synchronised(5.0));  // within the second: the state read before
  CHECK(kernel.reads == 1);
  kernel.now += 1ms;
  CHECK(watch.current() == synchronised(5.5));
  CHECK(kernel.reads == 2);
  for (int i = 0; i < 1000; ++i) (void)watch.current();
  CHECK(kernel.reads == 2);
}

TEST_CASE("clock watch: many threads asking at once make one read a second, and all see a state read") {
  FakeKernel kernel;
  ClockWatch watch(kernel.reader(), kernel.clock());
  kernel.next = unsynchronised();
  kernel.now += 1s;
  std::atomic<int> saw_read_state = 0;
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 10'000; ++i) {
        const ClockState state = watch.current();
        if (state == synchronised(5.0) || state == unsynchronised()) ++saw_read_state;
      }
    });
  }
  for (std::thread& t : threads) t.join();
  CHECK(kernel.reads == 2);  // made, and once for this second
  CHECK(saw_read_state == 80'000);
  CHECK(watch.current() == unsynchronised());
}

TEST_CASE("clock watch: losing the clock is logged once at warn, coming back once at info") {
  test::CapturedLog log(spdlog::level::info);
  FakeKernel kernel;
  ClockWatch watch(kernel.reader(), kernel.clock());
  CHECK(log.lines() ==
        std::vector<std::string>{
            "info clock: the system clock is synchronised, maximum error 5.0 ms"});
  kernel.next = unsynchronised();
  for (int second = 1; second <= 3; ++second) {
    kernel.now += 1s;
    CHECK_FALSE(watch.current().synchronised);
  }
  kernel.next = synchronised(0.5);
  for (int second = 4; second <= 6; ++second) {
    kernel.now += 1s;
    CHECK(watch.current().synchronised);
  }
  const auto lines = log.lines();
  REQUIRE(lines.size() == 3);
  CHECK(lines[1].starts_with("warning clock: the system clock is not synchronised (the kernel's "
                             "maximum-error bound reached 16 s"));
  CHECK(lines[1].ends_with("readings taken meanwhile are flagged"));
  CHECK(lines[2] == "info clock: the system clock is synchronised again, maximum error 0.5 ms");
  CHECK(watch.changes().losses == 1);
  CHECK(watch.changes().recoveries == 1);
}

TEST_CASE("clock watch: a clock unsynchronised from the start is one loss, said at once") {
  test::CapturedLog log(spdlog::level::info);
  FakeKernel kernel;
  kernel.next = unsynchronised();
  ClockWatch watch(kernel.reader(), kernel.clock());
  REQUIRE(log.lines().size() == 1);
  CHECK(log.lines()[0].starts_with("warning clock: the system clock is not synchronised"));
  CHECK(watch.changes().losses == 1);
  CHECK(watch.changes().recoveries == 0);
  kernel.now += 1s;
  (void)watch.current();
  CHECK(log.lines().size() == 1);
}

TEST_CASE("clock watch: a steady clock that did not move (or went back) never reads again early") {
  FakeKernel kernel;
  ClockWatch watch(kernel.reader(), kernel.clock());
  kernel.now -= 10s;  // a steady clock never does this; a bad fake must not make reads storm
  (void)watch.current();
  (void)watch.current();
  CHECK(kernel.reads == 1);
}
