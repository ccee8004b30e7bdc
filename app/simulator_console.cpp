#include "app/simulator_console.h"

#include <sys/stat.h>
#include <unistd.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <istream>
#include <utility>

namespace tiltgate {

namespace asio = boost::asio;

namespace {

// A line longer than this is not a command: the rest of it is dropped unread, and so is the
// console (a stream that never sends a newline cannot grow the buffer without end).
constexpr std::size_t kMaxLine = 1024;

bool is_pipe_or_socket(int fd) {
  struct stat st {};
  return ::fstat(fd, &st) == 0 && (S_ISFIFO(st.st_mode) || S_ISSOCK(st.st_mode));
}

}  // namespace

SimulatorConsole::SimulatorConsole(asio::io_context& io, BusSimulator& simulator, int input,
                                   std::function<void(const std::string&)> answer)
    : io_(io), simulator_(simulator), input_(input), answer_(std::move(answer)) {}

bool SimulatorConsole::start() {
  if (!is_pipe_or_socket(input_)) return false;
  const int fd = ::dup(input_);
  if (fd < 0) return false;
  stream_.emplace(io_, fd);
  asio::co_spawn(io_, read_lines(), asio::detached);
  return true;
}

void SimulatorConsole::stop() {
  if (!stream_) return;
  boost::system::error_code ignored;
  stream_->close(ignored);
}

asio::awaitable<void> SimulatorConsole::read_lines() {
  asio::streambuf buffer(kMaxLine);
  std::istream in(&buffer);
  while (stream_ && stream_->is_open()) {
    boost::system::error_code ec;
    co_await asio::async_read_until(*stream_, buffer, '\n',
                                    asio::redirect_error(asio::use_awaitable, ec));
    // End of input, a read error, closed at stop(), or a line over kMaxLine: no more commands.
    if (ec) co_return;
    std::string line;
    std::getline(in, line);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto done = simulator_.command(line);
    answer_(done ? std::string("ok") : "error: " + done.error());
  }
}

}  // namespace tiltgate
