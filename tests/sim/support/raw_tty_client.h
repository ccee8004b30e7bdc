// The gateway's side of a simulated bus in a test: a raw, non-blocking tty opened on the
// simulator's slave path (or its link). Single-threaded: while it waits for bytes it pumps the
// io_context the simulator runs on, always up to a deadline.
#pragma once

#include <sys/types.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace tiltgate::test {

// How long a reply is waited for: generous, since the machine may be busy.
inline constexpr std::chrono::milliseconds kReplyDeadline{2000};
// How long "no reply" is waited for.
inline constexpr std::chrono::milliseconds kSilence{300};

class RawTtyClient {
 public:
  RawTtyClient(boost::asio::io_context& io, const std::string& path);
  ~RawTtyClient();
  RawTtyClient(const RawTtyClient&) = delete;
  RawTtyClient& operator=(const RawTtyClient&) = delete;

  // Writes all of `bytes` (a failed or short write fails the test).
  void send(std::span<const std::uint8_t> bytes);

  // Pumps the io_context and reads, handing each chunk read to `feed`, until `take()` yields
  // something (returned) or `limit` has passed (nullopt).
  template <class Take, class Feed>
  auto wait_for(Take take, Feed feed, std::chrono::milliseconds limit) -> decltype(take()) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (true) {
      if (auto item = take()) return item;
      if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
      pump();
      const std::vector<std::uint8_t> chunk = read_available();
      feed(std::span<const std::uint8_t>(chunk));
      raw_.insert(raw_.end(), chunk.begin(), chunk.end());
    }
  }

  // The first `count` bytes received, or, when fewer came before `limit`, those.
  std::vector<std::uint8_t> first_bytes(std::size_t count,
                                        std::chrono::milliseconds limit = kReplyDeadline);
  // Every byte received once `limit` has passed: what came, and that nothing more did.
  std::vector<std::uint8_t> all_bytes_within(std::chrono::milliseconds limit = kSilence);

  // Every byte received so far, frames and garbage alike.
  const std::vector<std::uint8_t>& raw() const { return raw_; }

  // What one read of a byte on the tty returns now: bytes, or -1 with errno in `error`.
  ssize_t read_once(int& error);

 private:
  void pump();
  std::vector<std::uint8_t> read_available();

  boost::asio::io_context& io_;
  int fd_ = -1;
  std::vector<std::uint8_t> raw_;
};

// Runs the io_context until `done` holds (true) or `limit` passes (false).
template <class Predicate>
bool run_until(boost::asio::io_context& io, Predicate done,
               std::chrono::milliseconds limit = kReplyDeadline) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    io.restart();
    io.run_for(std::chrono::milliseconds(2));
  }
  return done();
}

}  // namespace tiltgate::test
