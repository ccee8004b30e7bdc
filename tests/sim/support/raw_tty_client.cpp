#include "sim/support/raw_tty_client.h"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <thread>

namespace tiltgate::test {

RawTtyClient::RawTtyClient(boost::asio::io_context& io, const std::string& path) : io_(io) {
  fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  REQUIRE_MESSAGE(fd_ >= 0, "cannot open " << path << ": " << std::strerror(errno));
  termios settings{};
  REQUIRE(::tcgetattr(fd_, &settings) == 0);
  ::cfmakeraw(&settings);
  REQUIRE(::tcsetattr(fd_, TCSANOW, &settings) == 0);
}

RawTtyClient::~RawTtyClient() { ::close(fd_); }

void RawTtyClient::send(std::span<const std::uint8_t> bytes) {
  REQUIRE(::write(fd_, bytes.data(), bytes.size()) == static_cast<ssize_t>(bytes.size()));
}

ssize_t RawTtyClient::read_once(int& error) {
  std::uint8_t byte = 0;
  const ssize_t n = ::read(fd_, &byte, 1);
  error = errno;
  return n;
}

std::vector<std::uint8_t> RawTtyClient::first_bytes(std::size_t count,
                                                    std::chrono::milliseconds limit) {
  const auto enough = [&]() -> std::optional<std::vector<std::uint8_t>> {
    if (raw_.size() < count) return std::nullopt;
    return std::vector<std::uint8_t>(raw_.begin(), raw_.begin() + count);
  };
  return wait_for(enough, [](std::span<const std::uint8_t>) {}, limit).value_or(raw_);
}

std::vector<std::uint8_t> RawTtyClient::all_bytes_within(std::chrono::milliseconds limit) {
  wait_for([]() -> std::optional<bool> { return std::nullopt; },
           [](std::span<const std::uint8_t>) {}, limit);
  return raw_;
}

void RawTtyClient::pump() {
  io_.restart();
  io_.run_for(std::chrono::milliseconds(2));
  // Nothing to run (unplugged, say): the loop would spin.
  if (io_.stopped()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

std::vector<std::uint8_t> RawTtyClient::read_available() {
  std::vector<std::uint8_t> bytes(512);
  const ssize_t n = ::read(fd_, bytes.data(), bytes.size());
  bytes.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  return bytes;
}

}  // namespace tiltgate::test
