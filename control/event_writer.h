// A running command's events on their way to the command line (control/control_session.h): the
// engine reports them as they happen, on the buses' thread, and must never wait for a slow
// reader; so each is queued here and written in order by a coroutine of its own. A command
// line that stops reading is not allowed to hold the gateway's memory: past kMaxQueuedBytes
// the writer gives up (broken()), and the session stops the command.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstddef>
#include <deque>
#include <memory>
#include <string>

namespace tiltgate {

class EventWriter : public std::enable_shared_from_this<EventWriter> {
 public:
  explicit EventWriter(boost::asio::local::stream_protocol::socket& socket);

  // Queues `line` (a newline is added); false when the writer has given up.
  bool push(std::string line);
  // Once every queued line is written, or the writer gave up: true; false when `deadline`
  // passed first (a command that stopped reading near the end of its run).
  boost::asio::awaitable<bool> drained(std::chrono::steady_clock::time_point deadline);
  bool broken() const { return broken_; }

  static constexpr std::size_t kMaxQueuedBytes = 16 * 1024 * 1024;

 private:
  boost::asio::awaitable<void> write_all();

  boost::asio::local::stream_protocol::socket& socket_;
  std::deque<std::string> queue_;
  std::size_t queued_bytes_ = 0;
  bool writing_ = false;
  bool broken_ = false;
  boost::asio::steady_timer idle_;  // cancelled each time the queue empties
};

}  // namespace tiltgate
