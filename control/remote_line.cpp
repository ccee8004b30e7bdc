#include "control/remote_line.h"

#include <boost/asio/read_until.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <istream>
#include <spdlog/spdlog.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "control/control_socket_io.h"
#include "driver/visible_text.h"
#include "serial/frame_trace.h"

namespace tiltgate {

namespace asio = boost::asio;
using local = asio::local::stream_protocol;
using Clock = std::chrono::steady_clock;

namespace {

// The longest a transaction can take on the gateway's side: its wait for a turn on the bus
// (the server's queue deadline, 10 s) and every attempt; past it the gateway is taken as hung.
std::chrono::milliseconds transaction_bound(const LineRequest& request) {
  const auto per_attempt = std::max(request.timeout, std::chrono::milliseconds(1000));
  const int attempts = request.retries < 0 ? 4 : request.retries + 1;
  return std::chrono::seconds(15) + per_attempt * attempts + request.settle;
}

struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
  int release() { return std::exchange(fd, -1); }
};

// Says this command's version first and reads the gateway's: the same protocol, or why not in
// one line that names both versions.
Expected<Done, std::string> agree_versions(int fd, const std::string& socket_path,
                                           Clock::time_point deadline) {
  const std::string version = control::format(control::CommandMessage{
      control::Version{control::kProtocolVersion, TILTGATE_VERSION}});
  if (auto sent = control::send_line(fd, version, deadline); !sent)
    return Unexpected{fmt::format("{}: cannot talk to the gateway: {}", socket_path, sent.error())};
  auto reply = control::read_line(fd, deadline);
  if (!reply)
    return Unexpected{fmt::format("{}: the gateway did not answer: {}", socket_path, reply.error())};
  const auto message = control::parse_gateway(*reply);
  const auto* agreed = message ? std::get_if<control::Version>(&*message) : nullptr;
  if (agreed != nullptr && agreed->protocol == control::kProtocolVersion) return Done{};
  const auto* refused = message ? std::get_if<control::Refused>(&*message) : nullptr;
  if (refused != nullptr && refused->reason.starts_with("malformed message \"version"))
    return Unexpected{fmt::format("{}: {}", socket_path, control::older_gateway(TILTGATE_VERSION))};
  return Unexpected{fmt::format("{}: {}", socket_path, visible_text(*reply))};
}

}  // namespace

RemoteLine::RemoteLine(local::socket socket, control::BusGranted bus)
    : socket_(std::move(socket)), bus_(std::move(bus)), name_(bus_.name) {}

Expected<std::unique_ptr<RemoteLine>, RemoteLine::ConnectError> RemoteLine::connect(
    asio::any_io_executor executor, const std::string& socket_path, const std::string& port,
    std::chrono::milliseconds timeout) {
  using Kind = ConnectError::Kind;
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  if (socket_path.size() >= sizeof(address.sun_path))
    return Unexpected{ConnectError{Kind::failed, fmt::format("{}: path too long", socket_path)}};
  std::memcpy(address.sun_path, socket_path.c_str(), socket_path.size() + 1);
  Fd socket{::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0)};
  if (socket.fd < 0)
    return Unexpected{ConnectError{Kind::failed, fmt::format("socket: {}", std::strerror(errno))}};
  // A Unix socket connects at once or not at all.
  if (::connect(socket.fd, reinterpret_cast<const sockaddr*>(&address), sizeof(address)) != 0) {
    const int error = errno;
    if (error == ENOENT || error == ECONNREFUSED || error == ENOTDIR)
      return Unexpected{ConnectError{
          Kind::no_gateway, fmt::format("no gateway is listening on {} ({})", socket_path,
                                        std::strerror(error))}};
    return Unexpected{ConnectError{
        Kind::failed,
        fmt::format("cannot connect to the gateway's control socket {}: {}{}", socket_path,
                    std::strerror(error),
                    error == EACCES ? " (is your user in the socket's group?)" : "")}};
  }
  const Clock::time_point deadline = Clock::now() + timeout;
  if (auto agreed = agree_versions(socket.fd, socket_path, deadline); !agreed)
    return Unexpected{ConnectError{Kind::failed, agreed.error()}};
  const std::string hello = control::format(control::CommandMessage{control::Hello{port}});
  if (auto sent = control::send_line(socket.fd, hello, deadline); !sent)
    return Unexpected{ConnectError{
        Kind::failed, fmt::format("{}: cannot talk to the gateway: {}", socket_path, sent.error())}};
  auto reply = control::read_line(socket.fd, deadline);
  if (!reply)
    return Unexpected{ConnectError{
        Kind::failed, fmt::format("{}: the gateway did not answer: {}", socket_path, reply.error())}};
  auto message = control::parse_gateway(*reply);
  if (message) {
    if (const auto* refused = std::get_if<control::Refused>(&*message))
      return Unexpected{ConnectError{Kind::not_served, refused->reason}};
    if (const auto* granted = std::get_if<control::BusGranted>(&*message)) {
      local::socket wrapped(executor);
      boost::system::error_code ec;
      wrapped.assign(local(), socket.fd, ec);
      if (ec) return Unexpected{ConnectError{Kind::failed, ec.message()}};
      socket.release();
      return std::unique_ptr<RemoteLine>(new RemoteLine(std::move(wrapped), *granted));
    }
  }
  return Unexpected{ConnectError{Kind::failed,
                                 fmt::format("{}: unexpected answer \"{}\"", socket_path, *reply)}};
}

void RemoteLine::stop() {
  stopped_ = true;
  boost::system::error_code ignored;
  socket_.close(ignored);
}

asio::awaitable<bool> RemoteLine::write_line(std::string line) {
  line += '\n';
  boost::system::error_code ec;
  co_await asio::async_write(socket_, asio::buffer(line), asio::redirect_error(asio::use_awaitable, ec));
  co_return !ec;
}

asio::awaitable<Expected<Done, LineError>> RemoteLine::transact(LineRequest request) {
  co_return co_await transact_in_turns(
      std::move(request), defaults_, timing_,
      [this](const LineRequest& one) { return attempt(one); });
}

asio::awaitable<Expected<Done, LineError>> RemoteLine::attempt(const LineRequest& request) {
  timing_ = LineTiming{};
  if (stopped_) co_return Unexpected{LineError::cancelled};
  if (!socket_.is_open()) co_return Unexpected{LineError::io};
  const bool tracing = spdlog::should_log(spdlog::level::trace);
  if (tracing)
    spdlog::trace("{} {}", name_, traced_request(request.bytes, request.address_bytes));
  ++stats_.attempts;
  std::string sent = control::format(control::CommandMessage{control::Transact{
      request.address_bytes, request.timeout, request.retries, request.settle,
      request.framer != nullptr, request.late_guard, request.bytes}});
  // A gateway that hangs mid-transaction must not hang the command: close the socket then.
  asio::steady_timer watchdog(co_await asio::this_coro::executor, transaction_bound(request));
  watchdog.async_wait([this](const boost::system::error_code& ec) {
    if (ec) return;
    boost::system::error_code ignored;
    socket_.close(ignored);
  });
  const Clock::time_point start = Clock::now();
  std::vector<std::uint8_t> received;  // for the trace log
  bool ok = co_await write_line(std::move(sent));
  while (ok) {
    boost::system::error_code ec;
    co_await asio::async_read_until(socket_, input_, '\n', asio::redirect_error(asio::use_awaitable, ec));
    if (ec) break;
    std::string line;
    std::istream stream(&input_);
    std::getline(stream, line);
    auto message = control::parse_gateway(line);
    if (!message) {
      spdlog::error("{}: {} from the gateway", name_, visible_text(message.error()));
      break;
    }
    if (std::holds_alternative<control::Reset>(*message)) {
      if (request.framer) request.framer->reset();
      received.clear();
    } else if (auto* chunk = std::get_if<control::Received>(&*message)) {
      const bool whole = request.framer != nullptr && request.framer->feed(chunk->bytes);
      if (tracing) received.insert(received.end(), chunk->bytes.begin(), chunk->bytes.end());
      // Formatted before the co_await: g++ 12 destroys a braced temporary there twice.
      std::string answer = control::format(control::CommandMessage{control::FramerAnswer{whole}});
      ok = co_await write_line(std::move(answer));
    } else if (const auto* ended = std::get_if<control::Ended>(&*message)) {
      watchdog.cancel();
      timing_ = ended->timing;
      generation_ = ended->generation;
      if (ended->busy) spdlog::warn("{}: the gateway's bus was too busy to send it", name_);
      if (tracing && request.framer) {
        const auto delay = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - start);
        if (!ended->error) {
          for (const std::string& traced : traced_reply(received, request.framer->report(), delay))
            spdlog::trace("{} {}", name_, traced);
        } else if (*ended->error == LineError::timeout) {
          spdlog::trace("{} {}", name_, traced_timeout(received, request.framer->report(), delay));
        }
      }
      if (!ended->error) co_return Done{};
      if (*ended->error == LineError::timeout) ++stats_.timeouts;
      co_return Unexpected{*ended->error};
    } else {
      spdlog::error("{}: unexpected \"{}\" from the gateway", name_, visible_text(line));
      break;
    }
  }
  watchdog.cancel();
  if (stopped_) co_return Unexpected{LineError::cancelled};
  // The session is lost (the gateway stopped, or it or we broke the protocol): every later
  // transaction fails at once.
  ++stats_.io_errors;
  stop();
  stopped_ = false;
  co_return Unexpected{LineError::io};
}

Expected<std::string, std::string> RemoteLine::ask(const control::CommandMessage& message) {
  if (!socket_.is_open()) return Unexpected{std::string("the gateway's connection is closed")};
  const std::string line = control::format(message) + "\n";
  boost::system::error_code ec;
  asio::write(socket_, asio::buffer(line), ec);
  if (!ec) asio::read_until(socket_, input_, '\n', ec);
  if (ec) return Unexpected{ec.message()};
  std::string reply;
  std::istream stream(&input_);
  std::getline(stream, reply);
  auto answer = control::parse_gateway(reply);
  if (const auto* ok = answer ? std::get_if<control::Followed>(&*answer) : nullptr) return ok->sensor;
  return Unexpected{fmt::format("unexpected answer \"{}\"", reply)};
}

Expected<std::string, std::string> RemoteLine::follow(std::uint32_t from, std::uint32_t to) {
  return ask(control::Follow{from, to});
}

Expected<std::string, std::string> RemoteLine::hold(std::uint32_t address) {
  return ask(control::Hold{address});
}

Expected<std::string, std::string> RemoteLine::release(std::uint32_t address) {
  return ask(control::Release{address});
}

Expected<std::string, std::string> RemoteLine::setting_changed(
    const control::SettingChanged& changed) {
  return ask(changed);
}

Expected<std::string, std::string> RemoteLine::act_for(const std::string& who) {
  return ask(control::ActingFor{who});
}

}  // namespace tiltgate
