// A TCP relay on its own thread that adds a fixed delay to each direction: every chunk read from
// one side is written to the other `one_way` later, in order. It puts a known round trip
// (2 x one_way) between the gateway's line and a device server on this machine, where the
// kernel has no netem. The bench's counterpart of tests/e2e/support/delay_relay.py, in C++ so
// its timers (timerfd, nanoseconds) add no rounding of their own to a 1 ms delay.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <string>
#include <thread>

namespace tiltgate::bench {

class TcpDelayRelay {
 public:
  // Listens on 127.0.0.1 (a free port) and relays each connection to 127.0.0.1:target_port.
  TcpDelayRelay(std::uint16_t target_port, std::chrono::microseconds one_way);
  ~TcpDelayRelay();
  TcpDelayRelay(const TcpDelayRelay&) = delete;
  TcpDelayRelay& operator=(const TcpDelayRelay&) = delete;

  std::uint16_t port() const { return port_; }

 private:
  boost::asio::io_context io_;
  std::uint16_t port_ = 0;
  std::thread thread_;
};

}  // namespace tiltgate::bench
