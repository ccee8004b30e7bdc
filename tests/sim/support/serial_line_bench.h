// A SerialLine against a scripted far end on the master side of a pseudo-terminal, both on one
// io_context, for the serial_line_*_test.cpp files.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "serial/pseudo_terminal.h"
#include "serial/serial_line.h"

namespace tiltgate::test::line_bench {

using Bytes = std::vector<std::uint8_t>;
using Clock = std::chrono::steady_clock;
using Result = tiltgate::Expected<tiltgate::Done, tiltgate::LineError>;

// Complete once `size` bytes have arrived; later bytes are ignored.
class CountFramer : public tiltgate::ReplyFramer {
 public:
  explicit CountFramer(std::size_t size) : size_(size) {}
  void reset() override { bytes.clear(); }
  bool feed(std::span<const std::uint8_t> chunk) override {
    ++feeds;
    for (std::uint8_t b : chunk) {
      if (bytes.size() < size_) bytes.push_back(b);
    }
    return bytes.size() == size_;
  }
  Bytes bytes;
  int feeds = 0;

 private:
  std::size_t size_;
};

// Complete at the first '\n'.
class LineEndFramer : public tiltgate::ReplyFramer {
 public:
  void reset() override { text.clear(); }
  bool feed(std::span<const std::uint8_t> chunk) override {
    for (std::uint8_t b : chunk) {
      text.push_back(char(b));
      if (b == '\n') return true;
    }
    return false;
  }
  std::string text;
};

Bytes bytes_of(const std::string& text);

// Braced lists cannot appear in an expression with co_await (g++ 12 rejects the
// initializer_list's backing array in a coroutine frame), so coroutines build bytes with this.
template <class... Byte>
Bytes octets(Byte... b) {
  return Bytes{std::uint8_t(b)...};
}

tiltgate::PseudoTerminal open_pty();

// The device side: the master end of the pty.
class FarEnd {
 public:
  FarEnd(boost::asio::io_context& io, tiltgate::PseudoTerminal& pty);

  // Exactly `size` bytes; notes when they were read.
  boost::asio::awaitable<Bytes> receive(std::size_t size);
  boost::asio::awaitable<void> send(Bytes bytes);
  // A device that never answers: reads and counts everything.
  boost::asio::awaitable<void> listen_silently();
  // The adapter is unplugged: the slave side hangs up.
  void close() { port_.close(); }
  int native() { return port_.native_handle(); }

  std::vector<Clock::time_point> arrivals;
  std::size_t received = 0;

 private:
  boost::asio::posix::stream_descriptor port_;
};

tiltgate::SerialLineOptions options_for(const std::string& port);

// Runs the io_context until `done` holds; false if it does not within `limit`.
bool run_until(boost::asio::io_context& io, const std::function<bool()>& done,
               Clock::duration limit = std::chrono::seconds(5));

// Polls `condition` every millisecond for up to `limit`, inside a coroutine.
boost::asio::awaitable<bool> eventually(std::function<bool()> condition,
                                        Clock::duration limit = std::chrono::seconds(3));

// One transaction run to its end (the test fails if it does not end within 5 s).
Result transact(boost::asio::io_context& io, tiltgate::SerialLine& line,
                tiltgate::LineRequest request);

tiltgate::LineRequest request_of(Bytes bytes, tiltgate::ReplyFramer* framer);

// Waits `how_long` on the coroutine's executor: a scripted device taking its time.
boost::asio::awaitable<void> pause(Clock::duration how_long);

// A pty whose far end the test scripts, and a started line on its slave side.
struct Bench {
  explicit Bench(const std::function<void(tiltgate::SerialLineOptions&)>& adjust = {});
  Result transact(tiltgate::LineRequest request);
  // Starts the device's script, then runs the transaction.
  Result exchange(tiltgate::LineRequest request, boost::asio::awaitable<void> device);

  boost::asio::io_context io;
  tiltgate::PseudoTerminal pty = open_pty();
  FarEnd far{io, pty};
  std::unique_ptr<tiltgate::SerialLine> line;
};

}  // namespace tiltgate::test::line_bench
