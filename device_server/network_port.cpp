#include "device_server/network_port.h"

#include "device_server/tcp_round_trip.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <cerrno>
#include <system_error>
#include <utility>

#include "driver/visible_text.h"

namespace tiltgate {

namespace asio = boost::asio;
using boost::system::error_code;

namespace {

// Keepalive finds a server host that vanished while the line was idle (about 10 + 3 x 5 s);
// the user time-out one that vanished while requests were unanswered at the TCP level.
constexpr int kKeepaliveIdleSeconds = 10;
constexpr int kKeepaliveIntervalSeconds = 5;
constexpr int kKeepaliveProbes = 3;
constexpr unsigned kUserTimeoutMs = 20000;

constexpr std::string_view kServerClosed = "the server closed the connection";

std::string errno_text(int error) {
  return std::error_code(error, std::generic_category()).message();
}

void set_option(int fd, int level, int name, int value) {
  (void)::setsockopt(fd, level, name, &value, sizeof value);
}

const char* framing_text(const rfc2217::PortSetting& s) {
  switch (s.parity) {
    case Parity::none: return s.stop_bits == 2 ? "8N2" : "8N1";
    case Parity::even: return "8E1";
    case Parity::odd: return "8O1";
    case Parity::mark: return "8M1";
    case Parity::space: return "8S1";
  }
  return "8N1";
}

}  // namespace

NetworkPort::NetworkPort(asio::any_io_executor executor, NetworkPortOptions options,
                         std::function<void()> on_reopened)
    : options_(std::move(options)),
      on_reopened_(std::move(on_reopened)),
      stream_(executor),
      resolver_(executor),
      timer_(executor) {
  options_.reopen_min = std::max(options_.reopen_min, std::chrono::milliseconds{1});
  options_.reopen_max = std::max(options_.reopen_max, options_.reopen_min);
  reopen_delay_ = options_.reopen_min;
}

NetworkPort::~NetworkPort() { stop(); }

bool NetworkPort::open() {
  // Only a port never opened starts connecting: otherwise it is open, stopped or connecting.
  if (!states_.on(NetworkPortEvent::open_asked)) return states_.is_open();
  reopen_delay_ = options_.reopen_min;
  asio::co_spawn(stream_.get_executor(), keep_connecting(alive_, std::chrono::milliseconds{0}),
                 asio::detached);
  return false;
}

void NetworkPort::stop() {
  states_.on(NetworkPortEvent::stop_asked);  // refused only when stopped already
  timer_.cancel();
  resolver_.cancel();
  close_socket();  // a pending read or write completes with operation_aborted
}

void NetworkPort::close_socket() {
  error_code ignored;
  stream_.close(ignored);
  fd_ = -1;
  telnet_.reset();
}

void NetworkPort::note_failure(const std::string& why) {
  // The texts this port and the line make of those errors (errno_text, read_negotiation,
  // discard_input; a read's end of file).
  PortFailure::Kind kind = PortFailure::Kind::other;
  if (why == errno_text(ECONNREFUSED))
    kind = PortFailure::Kind::refused;
  else if (why == errno_text(ECONNRESET) || why == errno_text(EPIPE) || why == kServerClosed ||
           why == error_code(asio::error::eof).message())
    kind = PortFailure::Kind::closed;
  failure_ = PortFailure{why, kind};
}

void NetworkPort::lose(const std::string& why) {
  close_socket();
  note_failure(why);
  // Stopped, or connecting already: the connect under way goes on.
  if (!states_.on(NetworkPortEvent::lost)) return;
  spdlog::warn("{}: connection to {} lost ({}), reconnecting", options_.name,
               visible_text(options_.url), why);
  reopen_delay_ = options_.reopen_min;
  asio::co_spawn(stream_.get_executor(), keep_connecting(alive_, reopen_delay_), asio::detached);
}

asio::awaitable<void> NetworkPort::keep_connecting(Alive alive, std::chrono::milliseconds delay) {
  for (;;) {
    if (delay.count() > 0) {
      timer_.expires_after(delay);
      error_code ec;
      co_await timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
      if (alive.expired() || states_.stopped()) co_return;
    }
    const Expected<Done, std::string> connected = co_await connect_once(alive);
    if (alive.expired()) co_return;
    if (states_.stopped()) {
      close_socket();
      co_return;
    }
    if (connected) break;
    close_socket();
    note_failure(connected.error());
    // The outage is warned of once: at the first connect's failure, or when the line lost it.
    const bool first_failure = states_.opening();
    states_.on(NetworkPortEvent::attempt_failed);
    if (first_failure) {
      spdlog::warn("{}: cannot connect to {} ({}), retrying", options_.name,
                   visible_text(options_.url), connected.error());
    } else {
      spdlog::debug("{}: {} still unavailable ({}), next try in {} ms", options_.name,
                    visible_text(options_.url), connected.error(), reopen_delay_.count());
    }
    delay = reopen_delay_;
    reopen_delay_ = std::min(reopen_delay_ * 2, options_.reopen_max);
  }
  states_.on(NetworkPortEvent::connected);
  failure_.reset();
  reopen_delay_ = options_.reopen_min;
  ++generation_;
  if (is_telnet()) {
    spdlog::info("{}: connected to {}, {} baud {} confirmed by the server", options_.name,
                 visible_text(options_.url), options_.setting.baud, framing_text(options_.setting));
  } else {
    spdlog::info("{}: connected to {}", options_.name, visible_text(options_.url));
  }
  if (generation_ > 1 && on_reopened_) on_reopened_();
}

void NetworkPort::arm_deadline(std::chrono::milliseconds limit) {
  states_.on(NetworkPortEvent::deadline_armed);
  timer_.expires_after(limit);
  timer_.async_wait([this, alive = Alive(alive_)](const error_code& ec) {
    if (ec || alive.expired()) return;
    states_.on(NetworkPortEvent::deadline_passed);
    resolver_.cancel();
    error_code ignored;
    stream_.cancel(ignored);
  });
}

asio::awaitable<Expected<Done, std::string>> NetworkPort::connect_once(Alive alive) {
  arm_deadline(options_.connect_timeout);
  error_code ec;
  const asio::ip::tcp::resolver::results_type endpoints = co_await resolver_.async_resolve(
      options_.address.host, std::to_string(options_.address.port),
      asio::redirect_error(asio::use_awaitable, ec));
  if (alive.expired()) co_return Unexpected(std::string("stopped"));
  if (ec) {
    timer_.cancel();
    co_return Unexpected(states_.deadline_passed() ? std::string("name lookup timed out")
                                          : "cannot resolve " + options_.address.host + ": " +
                                                ec.message());
  }
  std::string failure = "no address for " + options_.address.host;
  for (const auto& entry : endpoints) {
    const Expected<Done, std::string> connected = co_await connect_to(alive, entry.endpoint());
    if (alive.expired()) co_return Unexpected(std::string("stopped"));
    if (connected) {
      timer_.cancel();
      if (!is_telnet()) co_return Done{};
      arm_deadline(options_.connect_timeout);
      Expected<Done, std::string> negotiated = co_await negotiate(alive);
      if (!alive.expired()) timer_.cancel();
      co_return negotiated;
    }
    failure = connected.error();
    close_socket();
    if (states_.deadline_passed()) break;
  }
  timer_.cancel();
  co_return Unexpected(failure);
}

asio::awaitable<Expected<Done, std::string>> NetworkPort::connect_to(
    Alive alive, const asio::ip::tcp::endpoint& endpoint) {
  const int fd = ::socket(endpoint.protocol().family(), SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC,
                          IPPROTO_TCP);
  if (fd < 0) co_return Unexpected(errno_text(errno));
  set_option(fd, IPPROTO_TCP, TCP_NODELAY, 1);
  set_option(fd, SOL_SOCKET, SO_KEEPALIVE, 1);
  set_option(fd, IPPROTO_TCP, TCP_KEEPIDLE, kKeepaliveIdleSeconds);
  set_option(fd, IPPROTO_TCP, TCP_KEEPINTVL, kKeepaliveIntervalSeconds);
  set_option(fd, IPPROTO_TCP, TCP_KEEPCNT, kKeepaliveProbes);
  set_option(fd, IPPROTO_TCP, TCP_USER_TIMEOUT, int(kUserTimeoutMs));
  error_code ec;
  stream_.assign(fd, ec);
  if (ec) {
    ::close(fd);
    co_return Unexpected(ec.message());
  }
  fd_ = fd;
  if (::connect(fd, endpoint.data(), endpoint.size()) != 0) {
    if (errno != EINPROGRESS) co_return Unexpected(errno_text(errno));
    co_await stream_.async_wait(asio::posix::descriptor_base::wait_write,
                                asio::redirect_error(asio::use_awaitable, ec));
    if (alive.expired()) co_return Unexpected(std::string("stopped"));
    if (ec) {
      co_return Unexpected(states_.deadline_passed() ? std::string("connect timed out")
                                                     : ec.message());
    }
    int error = 0;
    socklen_t size = sizeof error;
    if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &size) != 0) error = errno;
    if (error != 0) co_return Unexpected(errno_text(error));
  }
  co_return Done{};
}

asio::awaitable<Expected<Done, std::string>> NetworkPort::send_all(
    Alive alive, std::vector<std::uint8_t> bytes) {
  std::span<const std::uint8_t> rest(bytes);
  while (!rest.empty()) {
    const Expected<std::size_t, std::string> sent = write_now(rest);
    if (!sent) co_return Unexpected(sent.error());
    rest = rest.subspan(*sent);
    if (rest.empty()) break;
    error_code ec;
    co_await stream_.async_wait(asio::posix::descriptor_base::wait_write,
                                asio::redirect_error(asio::use_awaitable, ec));
    if (alive.expired()) co_return Unexpected(std::string("stopped"));
    if (ec) co_return Unexpected(ec.message());
  }
  co_return Done{};
}

asio::awaitable<Expected<Done, std::string>> NetworkPort::read_negotiation(Alive alive) {
  std::array<std::uint8_t, 256> buffer{};
  error_code ec;
  const std::size_t received = co_await stream_.async_read_some(
      asio::buffer(buffer), asio::redirect_error(asio::use_awaitable, ec));
  if (alive.expired()) co_return Unexpected(std::string("stopped"));
  if (ec == asio::error::eof) co_return Unexpected(std::string(kServerClosed));
  if (ec) co_return Unexpected(ec.message());
  // Data bytes before the port is set (a sensor's chatter at the old rate) mean nothing.
  (void)incoming(std::span(buffer.data(), received));
  co_return Done{};
}

asio::awaitable<Expected<Done, std::string>> NetworkPort::negotiate(Alive alive) {
  telnet_.emplace(options_.setting);
  Expected<Done, std::string> sent = co_await send_all(alive, Rfc2217Session::offer());
  if (alive.expired()) co_return Unexpected(std::string("stopped"));
  if (!sent) co_return sent;
  // The server agrees to the COM-PORT-OPTION (DO) before it takes any of its commands.
  while (!telnet_->agreed() && !telnet_->refusal()) {
    const Expected<Done, std::string> read = co_await read_negotiation(alive);
    if (alive.expired()) co_return Unexpected(std::string("stopped"));
    if (!read) {
      co_return Unexpected(states_.deadline_passed()
                               ? std::string("no answer to the RFC 2217 negotiation (is the "
                                             "server's port in RFC 2217 mode? A port in raw TCP "
                                             "mode is tcp://)")
                               : read.error());
    }
  }
  if (const auto refused = telnet_->refusal()) co_return Unexpected(*refused);
  sent = co_await send_all(alive, telnet_->setting_requests());
  if (alive.expired()) co_return Unexpected(std::string("stopped"));
  if (!sent) co_return sent;
  while (!telnet_->confirmed()) {
    const Expected<Done, std::string> read = co_await read_negotiation(alive);
    if (alive.expired()) co_return Unexpected(std::string("stopped"));
    if (!read) {
      co_return Unexpected(states_.deadline_passed()
                               ? "the server did not confirm the " + telnet_->missing() +
                                     " within " +
                                     std::to_string(options_.connect_timeout.count()) + " ms"
                               : read.error());
    }
    if (const auto refused = telnet_->refusal()) co_return Unexpected(*refused);
  }
  co_return Done{};
}

Expected<std::size_t, std::string> NetworkPort::write_now(std::span<const std::uint8_t> bytes) {
  for (;;) {
    const ssize_t sent = ::send(stream_.native_handle(), bytes.data(), bytes.size(),
                                MSG_NOSIGNAL | MSG_DONTWAIT);
    if (sent >= 0) return std::size_t(sent);
    if (errno == EAGAIN || errno == EWOULDBLOCK) return std::size_t{0};
    if (errno != EINTR) return Unexpected(errno_text(errno));
  }
}

Expected<std::size_t, std::string> NetworkPort::discard_input() {
  std::array<std::uint8_t, 512> buffer{};
  std::size_t dropped = 0;  // the line's bytes, a Telnet port's commands taken out
  for (;;) {
    const ssize_t received =
        ::recv(stream_.native_handle(), buffer.data(), buffer.size(), MSG_DONTWAIT);
    if (received > 0) {
      dropped += incoming(std::span(buffer.data(), std::size_t(received)));
      continue;
    }
    if (received == 0) return Unexpected(std::string(kServerClosed));
    if (errno == EAGAIN || errno == EWOULDBLOCK) return dropped;
    if (errno != EINTR) return Unexpected(errno_text(errno));
  }
}

std::span<const std::uint8_t> NetworkPort::outgoing(std::span<const std::uint8_t> bytes) {
  return telnet_ ? telnet_->escaped(bytes) : bytes;
}

std::size_t NetworkPort::incoming(std::span<std::uint8_t> chunk) {
  if (!telnet_) return chunk.size();
  const std::size_t data = telnet_->take(chunk);
  // Three bytes at most per option on an idle socket; a lost one only leaves it offered.
  if (const std::vector<std::uint8_t> replies = telnet_->take_replies(); !replies.empty())
    (void)write_now(replies);
  return data;
}

Expected<Done, std::string> NetworkPort::switch_parity(Parity) {
  return Unexpected(std::string("a parity per byte cannot be carried to a device server"));
}

std::chrono::microseconds NetworkPort::network_allowance() const {
  const std::optional<TcpRoundTrip> measured = read_round_trip(fd_);
  if (!measured) return {};
  return measured->smoothed + 4 * measured->variation;
}

std::chrono::microseconds NetworkPort::round_trip() const {
  const std::optional<TcpRoundTrip> measured = read_round_trip(fd_);
  return measured ? measured->least : std::chrono::microseconds{0};
}

}  // namespace tiltgate
