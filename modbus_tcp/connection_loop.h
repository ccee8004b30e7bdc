// One thread's event loop for the Modbus TCP connections it serves: an epoll set of their
// sockets, the tasks other threads hand it, and their deadlines. Not Asio's reactor: for a
// request-and-reply protocol Asio costs one system call more per request (a speculative recv
// that finds nothing, or an epoll_ctl to re-arm), and on a small virtual machine a system call
// is a few percent of a read's whole cost (docs/performance.md, "The Modbus read path").
//
// Sockets are watched edge-triggered for input and output from the moment they are added: a
// client reads its socket until a read comes back short and then waits for the next event, so
// a read costs one epoll_wait, one recv and one send, and one wake-up answers every client
// whose request came in meanwhile.
//
// Deadlines are swept, not timed one by one: a client says when it wants to be looked at again
// (wake_by), the loop sleeps no longer than the earliest such time and then asks every client
// (on_deadline). Deadlines move later with nearly every request; a sweep sees that, and no
// timer is touched per request. The loop's sleep has no time-out of its own: a timerfd in the
// epoll set wakes it for a sweep, set only when the sweep is wanted sooner than it is set for,
// or again when it fires. An epoll_wait with a time-out arms and cancels a kernel timer every
// time it sleeps, which cost about 3 % of a read at one client (docs/performance.md).
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "driver/expected.h"

namespace tiltgate {

class ConnectionLoop {
 public:
  using Clock = std::chrono::steady_clock;

  // What the loop serves: a socket's owner, called on the loop's thread only.
  class Client {
   public:
    virtual ~Client() = default;
    // Its socket's epoll events (EPOLLIN, EPOLLOUT, EPOLLERR, EPOLLHUP, EPOLLRDHUP).
    virtual void on_events(std::uint32_t events) = 0;
    // A sweep: handles what is due at `now` and says when it is next due (max: nothing due).
    virtual Clock::time_point on_deadline(Clock::time_point now) = 0;
  };

  // The epoll set and the wake-up descriptor; std::system_error when the system has none left.
  ConnectionLoop();
  ~ConnectionLoop();
  ConnectionLoop(const ConnectionLoop&) = delete;
  ConnectionLoop& operator=(const ConnectionLoop&) = delete;

  // Serves until stop(): then it returns once it has no client left, or at once with
  // `now`. The thread that calls it is the loop's thread.
  void run();
  // Any thread. Ends run() once every client has been removed, or with `now` at once (the
  // clients left are abandoned: their owners close them).
  void stop(bool now = false);
  bool stopped() const { return ended_; }

  // Any thread: `task` runs on the loop's thread, after what was posted before it.
  void post(std::function<void()> task);

  // The loop's thread. Watches `fd` for `client`, which the loop keeps alive until remove().
  Expected<Done, std::string> add(int fd, std::shared_ptr<Client> client);
  // Stops watching `fd` (before it is closed) and lets go of `client` once the current
  // event has been handled.
  void remove(int fd, const Client& client);
  // `client`'s next deadline is at `when` or later: the loop sweeps by then.
  void wake_by(Clock::time_point when) {
    if (when < next_sweep_) next_sweep_ = when;
  }
  // The time the current turn of the loop began: what a client measures its deadlines from.
  Clock::time_point now() const { return now_; }

 private:
  void run_posted();
  void sweep();
  // Sets the timerfd for next_sweep_ when it is set for later (or not at all).
  void arm_sweep_timer();
  int wait_ms() const;

  int epoll_fd_ = -1;
  int wake_fd_ = -1;   // an eventfd: post() and stop() write it
  int timer_fd_ = -1;  // a timerfd: wakes the loop for a sweep
  std::mutex posted_mutex_;
  std::vector<std::function<void()>> posted_;
  std::vector<std::function<void()>> running_;  // the loop's: posted_ swapped out
  std::atomic<bool> stopping_ = false, stopping_now_ = false, ended_ = false;
  // The loop's thread only.
  std::vector<std::shared_ptr<Client>> clients_;
  std::vector<std::shared_ptr<Client>> removed_;   // let go after the current turn
  std::vector<std::shared_ptr<Client>> sweeping_;  // sweep()'s copy of clients_
  Clock::time_point now_ = Clock::now();
  Clock::time_point next_sweep_ = Clock::time_point::max();
  Clock::time_point timer_set_for_ = Clock::time_point::max();  // max: not set
};

}  // namespace tiltgate
