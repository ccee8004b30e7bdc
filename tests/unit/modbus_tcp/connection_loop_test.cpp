// ConnectionLoop's deadlines: the loop sleeps without a time-out of its own and is woken for a
// sweep by its timer, which it sets only when a sweep is wanted sooner than the timer is set
// for, and again when it fires. Each case fails when one of those settings is left out: the
// loop then sleeps past the deadline (these tests give it a second).
#include <doctest/doctest.h>

#include <unistd.h>

#include <chrono>
#include <future>
#include <memory>
#include <optional>
#include <thread>

#include "modbus_tcp/connection_loop.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using Clock = ConnectionLoop::Clock;

namespace {

// A client with one deadline and a socket that never has an event (a pipe nobody writes):
// only a sweep reaches it. It reports the first sweep that finds its deadline due.
class DeadlineClient final : public ConnectionLoop::Client {
 public:
  explicit DeadlineClient(Clock::time_point due) : due_(due) {}
  void on_events(std::uint32_t) override {}
  Clock::time_point on_deadline(Clock::time_point now) override {
    if (now < due_) return due_;
    if (!reported_) {
      reported_ = true;
      swept_.set_value(now);
    }
    return Clock::time_point::max();
  }
  // Loop thread only: the deadline the client gives the next sweep.
  void move_to(Clock::time_point due) { due_ = due; }
  std::future<Clock::time_point> swept() { return swept_.get_future(); }

 private:
  Clock::time_point due_;
  bool reported_ = false;
  std::promise<Clock::time_point> swept_;
};

// A loop on its own thread, with one pipe whose read end its client is watched on.
struct RunningLoop {
  ConnectionLoop loop;
  int pipe_fds[2] = {-1, -1};
  std::thread thread;

  RunningLoop() {
    REQUIRE(::pipe(pipe_fds) == 0);
    thread = std::thread([this] { loop.run(); });
  }
  ~RunningLoop() {
    loop.stop(true);
    thread.join();
    ::close(pipe_fds[0]);
    ::close(pipe_fds[1]);
  }

  // Adds `client` on the loop's thread, due at `due`.
  void add(const std::shared_ptr<DeadlineClient>& client, Clock::time_point due) {
    std::promise<void> added;
    loop.post([&] {
      const bool watched = bool(loop.add(pipe_fds[0], client));
      CHECK(watched);
      loop.wake_by(due);
      added.set_value();
    });
    added.get_future().wait();
  }

  // Runs `task` on the loop's thread and waits for it.
  template <class Task>
  void on_loop(Task task) {
    std::promise<void> done;
    loop.post([&] {
      task();
      done.set_value();
    });
    done.get_future().wait();
  }
};

// When the client was swept, or nothing if it was not within a second of `due`.
std::optional<Clock::time_point> swept_by(std::future<Clock::time_point>& swept,
                                          Clock::time_point due) {
  if (swept.wait_until(due + 1s) != std::future_status::ready) return std::nullopt;
  return swept.get();
}

}  // namespace

TEST_CASE("connection loop: a deadline is swept when due, with nothing else to wake the loop") {
  RunningLoop running;
  const auto due = Clock::now() + 50ms;
  auto client = std::make_shared<DeadlineClient>(due);
  auto swept = client->swept();
  running.add(client, due);
  const auto at = swept_by(swept, due);
  REQUIRE(at.has_value());
  CHECK(*at >= due);
}

namespace {

// A client first due `first` from now, its deadline then moved to `moved` from now (with
// wake_by as a sooner deadline needs, or without as a request moves it later): when it was
// swept, nothing if not within a second of the moved deadline, which it returns too.
struct Moved {
  std::optional<Clock::time_point> swept;
  Clock::time_point due;
};
Moved moved_deadline(Clock::duration first, Clock::duration moved, bool wake_loop) {
  RunningLoop running;
  const auto first_due = Clock::now() + first;
  auto client = std::make_shared<DeadlineClient>(first_due);
  auto swept = client->swept();
  running.add(client, first_due);  // the timer is set for `first`
  const auto due = Clock::now() + moved;
  running.on_loop([&] {
    client->move_to(due);
    if (wake_loop) running.loop.wake_by(due);
  });
  return {swept_by(swept, due), due};
}

}  // namespace

TEST_CASE("connection loop: a deadline brought forward is swept at the sooner time") {
  const Moved moved = moved_deadline(10s, 50ms, true);
  REQUIRE(moved.swept.has_value());
  CHECK(*moved.swept >= moved.due);
}

TEST_CASE("connection loop: a deadline moved later is swept then, after the timer set sooner fired") {
  // No wake_by, as a request moves it: the sweep at 50 ms finds it moved.
  const Moved moved = moved_deadline(50ms, 300ms, false);
  REQUIRE(moved.swept.has_value());
  CHECK(*moved.swept >= moved.due);
}
