// A line's port on a serial device server (docs/operations.md, "Serial device servers"): one
// TCP connection, standing in for the tty, that the SerialLine moves its bytes through.
//
// tcp://     raw: the server passes bytes both ways; its serial port's rate and framing are
//            set on the server itself.
// rfc2217:// Telnet (RFC 854) with the COM-PORT-OPTION (RFC 2217): after connecting, the port
//            asks for binary mode and the option, then sets the far port's rate, data size,
//            parity and stop bits from the bus's keys, and is open only once the server has
//            confirmed those four as asked (device_server/com_port_option.h). Options the
//            server cannot apply (modem lines, flow control) are not waited for. Data bytes
//            0xFF are doubled on the way out and Telnet commands taken out on the way in.
//
// A connection that cannot be made, or is lost (the server closed it, a reset, keepalive's
// verdict on a dead host), is a tty gone: the port is closed, so every sensor of the bus goes
// offline, and it is made again with back-off from reopen_min to reopen_max; every successful
// connection counts one generation, as a tty's reopen does. The host name is resolved at each
// connect, so a server that changes address is found again. TCP keepalive and a user time-out
// find a server that vanished without closing; TCP_NODELAY sends each request at once.
//
// The network's share of a reply's time is measured per connection from the kernel's own
// round-trip estimate (TCP_INFO): network_allowance() is added to every reply wait.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "device_server/com_port_option.h"
#include "device_server/network_port_state.h"
#include "device_server/port_url.h"
#include "device_server/rfc2217_session.h"
#include "serial/line_port.h"

namespace tiltgate {

struct NetworkPortOptions {
  std::string name;     // the bus's, for log lines
  std::string url;      // as configured, for log lines
  PortAddress address;  // a tcp or rfc2217 address
  rfc2217::PortSetting setting;  // what an rfc2217:// port sets on the far port
  std::chrono::milliseconds reopen_min{500};
  std::chrono::milliseconds reopen_max{10000};
  // The longest a connect, or the server's answers to RFC 2217's requests, may take.
  std::chrono::milliseconds connect_timeout{3000};
};

class NetworkPort final : public LinePort {
 public:
  // `on_reopened` is called after each successful connect but the first.
  NetworkPort(boost::asio::any_io_executor executor, NetworkPortOptions options,
              std::function<void()> on_reopened);
  ~NetworkPort() override;
  NetworkPort(const NetworkPort&) = delete;
  NetworkPort& operator=(const NetworkPort&) = delete;

  // Starts connecting; the port is open once connected (and, over RFC 2217, confirmed).
  bool open() override;
  void stop() override;
  void lose(const std::string& why) override;

  bool is_open() const override { return states_.is_open(); }
  bool opening() const override { return states_.opening(); }
  std::optional<PortFailure> failure() const override {
    return states_.is_open() ? std::nullopt : failure_;
  }
  bool stopped() const override { return states_.stopped(); }
  std::uint64_t generation() const override { return generation_; }
  boost::asio::posix::stream_descriptor& stream() override { return stream_; }

  Expected<std::size_t, std::string> write_now(std::span<const std::uint8_t> bytes) override;
  // Reads and drops what the socket holds (a late answer), taking Telnet commands out.
  Expected<std::size_t, std::string> discard_input() override;
  std::span<const std::uint8_t> outgoing(std::span<const std::uint8_t> bytes) override;
  std::size_t incoming(std::span<std::uint8_t> chunk) override;
  // A parity per byte cannot be carried over a network (config refuses 9-bit buses there).
  Expected<Done, std::string> switch_parity(Parity parity) override;
  Expected<Done, std::string> wait_until_sent() override { return Done{}; }

  // The kernel's smoothed round trip plus four times its variation (as TCP's own
  // retransmission time-out is reckoned).
  std::chrono::microseconds network_allowance() const override;
  // The least round trip seen on the connection.
  std::chrono::microseconds round_trip() const override;

 private:
  using Alive = std::weak_ptr<int>;

  // Connects, after `delay`, again and again with back-off until it succeeds or stops.
  boost::asio::awaitable<void> keep_connecting(Alive alive, std::chrono::milliseconds delay);
  boost::asio::awaitable<Expected<Done, std::string>> connect_once(Alive alive);
  boost::asio::awaitable<Expected<Done, std::string>> connect_to(
      Alive alive, const boost::asio::ip::tcp::endpoint& endpoint);
  // RFC 2217: option negotiation, then the far port's settings, confirmed.
  boost::asio::awaitable<Expected<Done, std::string>> negotiate(Alive alive);
  // Sends all of `bytes` on the connection being made.
  boost::asio::awaitable<Expected<Done, std::string>> send_all(Alive alive,
                                                               std::vector<std::uint8_t> bytes);
  // One read during negotiation, through the session (data bytes dropped).
  boost::asio::awaitable<Expected<Done, std::string>> read_negotiation(Alive alive);
  // Cancels what the connect is waiting for when `limit` has passed.
  void arm_deadline(std::chrono::milliseconds limit);
  void close_socket();
  bool is_telnet() const { return options_.address.scheme == PortScheme::rfc2217; }

  NetworkPortOptions options_;
  std::function<void()> on_reopened_;
  boost::asio::posix::stream_descriptor stream_;
  boost::asio::ip::tcp::resolver resolver_;
  boost::asio::steady_timer timer_;  // the back-off, and the connect's deadline
  std::chrono::milliseconds reopen_delay_;
  NetworkPortStates states_;  // closed, opening, reconnecting, open, stopped
  std::uint64_t generation_ = 0;
  int fd_ = -1;  // the socket's, for TCP_INFO; -1 while closed
  std::optional<PortFailure> failure_;  // the latest failed connect or lost connection
  // Records `why` as the latest failure, and whether it says the server refused, closed or
  // reset the connection.
  void note_failure(const std::string& why);
  // The RFC 2217 conversation of the connection being made or open (rfc2217:// only).
  std::optional<Rfc2217Session> telnet_;
  // Lets handlers and the connect coroutine that outlive the port see that it is gone.
  std::shared_ptr<int> alive_ = std::make_shared<int>(0);
};

}  // namespace tiltgate
