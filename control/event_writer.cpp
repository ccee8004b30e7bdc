#include "control/event_writer.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>

namespace tiltgate {

namespace asio = boost::asio;

EventWriter::EventWriter(asio::local::stream_protocol::socket& socket)
    : socket_(socket), idle_(socket.get_executor()) {}

bool EventWriter::push(std::string line) {
  if (broken_) return false;
  line += '\n';
  queued_bytes_ += line.size();
  if (queued_bytes_ > kMaxQueuedBytes) {
    broken_ = true;
    queue_.clear();
    return false;
  }
  queue_.push_back(std::move(line));
  if (!writing_) {
    writing_ = true;
    asio::co_spawn(socket_.get_executor(),
                   [self = shared_from_this()] { return self->write_all(); }, asio::detached);
  }
  return true;
}

asio::awaitable<void> EventWriter::write_all() {
  while (!queue_.empty() && !broken_) {
    boost::system::error_code ec;
    co_await asio::async_write(socket_, asio::buffer(queue_.front()),
                               asio::redirect_error(asio::use_awaitable, ec));
    if (ec) {
      broken_ = true;
      queue_.clear();
      break;
    }
    queued_bytes_ -= queue_.front().size();
    queue_.pop_front();
  }
  writing_ = false;
  idle_.cancel();
}

asio::awaitable<bool> EventWriter::drained(std::chrono::steady_clock::time_point deadline) {
  while (writing_ && std::chrono::steady_clock::now() < deadline) {
    idle_.expires_at(deadline);
    boost::system::error_code ec;
    co_await idle_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
  co_return !writing_;
}

}  // namespace tiltgate
