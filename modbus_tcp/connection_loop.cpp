#include "modbus_tcp/connection_loop.h"

#include <sys/epoll.h>
#include <sys/eventfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <ctime>
#include <spdlog/spdlog.h>
#include <system_error>

namespace tiltgate {

namespace {

// Events a socket is watched for, all its life: input and output, edge-triggered.
constexpr std::uint32_t kSocketEvents = EPOLLIN | EPOLLOUT | EPOLLRDHUP | EPOLLET;

}  // namespace

ConnectionLoop::ConnectionLoop() {
  epoll_fd_ = ::epoll_create1(EPOLL_CLOEXEC);
  if (epoll_fd_ < 0) throw std::system_error(errno, std::generic_category(), "epoll_create1");
  wake_fd_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  timer_fd_ = ::timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC | TFD_NONBLOCK);
  if (wake_fd_ < 0 || timer_fd_ < 0) {
    const int error = errno;
    if (wake_fd_ >= 0) ::close(wake_fd_);
    if (timer_fd_ >= 0) ::close(timer_fd_);
    ::close(epoll_fd_);
    throw std::system_error(error, std::generic_category(), "eventfd/timerfd_create");
  }
  // Level-triggered: readable until run_posted() has read it.
  epoll_event event{};
  event.events = EPOLLIN;
  event.data.ptr = nullptr;
  ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, wake_fd_, &event);
  // The timer's events carry the loop's own address, which no client has.
  event.data.ptr = this;
  ::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, timer_fd_, &event);
}

ConnectionLoop::~ConnectionLoop() {
  ::close(timer_fd_);
  ::close(wake_fd_);
  ::close(epoll_fd_);
}

void ConnectionLoop::run() {
  std::array<epoll_event, 64> events{};
  while (!stopping_now_) {
    if (stopping_ && clients_.empty()) {
      run_posted();  // what was posted before stop() still runs
      if (clients_.empty()) break;
    }
    arm_sweep_timer();
    const int n = ::epoll_wait(epoll_fd_, events.data(), int(events.size()), wait_ms());
    now_ = Clock::now();
    if (n < 0 && errno != EINTR) {
      spdlog::error("Modbus TCP thread: epoll_wait: {}", std::strerror(errno));
      break;
    }
    for (int i = 0; i < n; ++i) {
      void* owner = events[std::size_t(i)].data.ptr;
      if (owner == nullptr) {
        run_posted();
      } else if (owner == this) {
        std::uint64_t expirations = 0;
        [[maybe_unused]] const auto read = ::read(timer_fd_, &expirations, sizeof expirations);
        timer_set_for_ = Clock::time_point::max();  // fired: set again before the wait
      } else {
        static_cast<Client*>(owner)->on_events(events[std::size_t(i)].events);
      }
    }
    if (now_ >= next_sweep_) sweep();
    removed_.clear();
  }
  ended_ = true;
}

void ConnectionLoop::stop(bool now) {
  stopping_ = true;
  if (now) stopping_now_ = true;
  const std::uint64_t one = 1;
  [[maybe_unused]] const auto written = ::write(wake_fd_, &one, sizeof one);
}

void ConnectionLoop::post(std::function<void()> task) {
  bool was_empty = false;
  {
    std::lock_guard lock(posted_mutex_);
    was_empty = posted_.empty();
    posted_.push_back(std::move(task));
  }
  // One wake-up for a burst of tasks: the loop takes them all at once.
  if (was_empty) {
    const std::uint64_t one = 1;
    [[maybe_unused]] const auto written = ::write(wake_fd_, &one, sizeof one);
  }
}

void ConnectionLoop::run_posted() {
  std::uint64_t count = 0;
  [[maybe_unused]] const auto read = ::read(wake_fd_, &count, sizeof count);
  {
    std::lock_guard lock(posted_mutex_);
    running_.swap(posted_);
  }
  // A throwing task is a bug; it costs that task, not the thread.
  for (auto& task : running_) {
    try {
      task();
    } catch (const std::exception& e) {
      spdlog::error("Modbus TCP thread: {}", e.what());
    }
  }
  running_.clear();
}

Expected<Done, std::string> ConnectionLoop::add(int fd, std::shared_ptr<Client> client) {
  epoll_event event{};
  event.events = kSocketEvents;
  event.data.ptr = client.get();
  if (::epoll_ctl(epoll_fd_, EPOLL_CTL_ADD, fd, &event) != 0)
    return Unexpected(std::string("epoll_ctl: ") + std::strerror(errno));
  clients_.push_back(std::move(client));
  return Done{};
}

void ConnectionLoop::remove(int fd, const Client& client) {
  ::epoll_ctl(epoll_fd_, EPOLL_CTL_DEL, fd, nullptr);
  const auto it = std::find_if(clients_.begin(), clients_.end(),
                               [&](const auto& kept) { return kept.get() == &client; });
  if (it == clients_.end()) return;
  // An event for it may still wait in this turn's list: it lives until the turn ends.
  removed_.push_back(std::move(*it));
  clients_.erase(it);
}

void ConnectionLoop::sweep() {
  next_sweep_ = Clock::time_point::max();
  // Over a copy: a client may remove itself from clients_ as it is asked.
  sweeping_.assign(clients_.begin(), clients_.end());
  for (const auto& client : sweeping_) wake_by(client->on_deadline(now_));
  sweeping_.clear();
}

void ConnectionLoop::arm_sweep_timer() {
  // A sweep wanted later than the timer is set for finds nothing due when the timer fires and
  // sets it again: deadlines that move later cost nothing until then.
  if (next_sweep_ >= timer_set_for_) return;
  // At least 1 ns: a time of zero would unset the timer instead.
  const auto since_boot = std::chrono::duration_cast<std::chrono::nanoseconds>(
      std::max(next_sweep_.time_since_epoch(), Clock::duration{1}));
  itimerspec when{};
  when.it_value.tv_sec = std::time_t(since_boot.count() / 1000000000);
  when.it_value.tv_nsec = long(since_boot.count() % 1000000000);
  // steady_clock is CLOCK_MONOTONIC, the timerfd's clock: an absolute time on it.
  if (::timerfd_settime(timer_fd_, TFD_TIMER_ABSTIME, &when, nullptr) != 0) {
    spdlog::error("Modbus TCP thread: timerfd_settime: {}", std::strerror(errno));
    return;
  }
  timer_set_for_ = next_sweep_;
}

int ConnectionLoop::wait_ms() const {
  return stopping_now_ || (stopping_ && clients_.empty()) ? 0 : -1;
}

}  // namespace tiltgate
