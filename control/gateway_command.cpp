#include "control/gateway_command.h"

#include <boost/asio/read_until.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <istream>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include "control/control_socket_io.h"
#include "driver/visible_text.h"

namespace tiltgate {

namespace asio = boost::asio;
using local = asio::local::stream_protocol;
using Clock = std::chrono::steady_clock;

namespace {

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

GatewayCommand::GatewayCommand(local::socket socket, std::string socket_path,
                               control::BusGranted bus)
    : socket_(std::move(socket)), socket_path_(std::move(socket_path)), bus_(std::move(bus)) {}

Expected<std::unique_ptr<GatewayCommand>, GatewayCommand::ConnectError> GatewayCommand::connect(
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
      return std::unique_ptr<GatewayCommand>(new GatewayCommand(std::move(wrapped), socket_path, *granted));
    }
  }
  return Unexpected{ConnectError{Kind::failed,
                                 fmt::format("{}: unexpected answer \"{}\"", socket_path, *reply)}};
}

void GatewayCommand::stop() {
  boost::system::error_code ignored;
  if (++stops_ > 1) {
    socket_.close(ignored);
    return;
  }
  stop_line_ = control::format(control::CommandMessage{control::Stop{}}) + "\n";
  asio::async_write(socket_, asio::buffer(stop_line_), [](const boost::system::error_code&,
                                                          std::size_t) {});
}

asio::awaitable<Expected<int, std::string>> GatewayCommand::run(
    std::string request, std::function<void(const std::string&)> on_event) {
  std::string sent = control::format(control::CommandMessage{control::Run{std::move(request)}}) + "\n";
  boost::system::error_code ec;
  co_await asio::async_write(socket_, asio::buffer(sent), asio::redirect_error(asio::use_awaitable, ec));
  if (ec)
    co_return Unexpected{fmt::format("{}: cannot talk to the gateway: {}", socket_path_, ec.message())};
  for (;;) {
    co_await asio::async_read_until(socket_, input_, '\n', asio::redirect_error(asio::use_awaitable, ec));
    if (ec) {
      if (stops_ > 1) co_return 0;  // stopped twice: the engineer stopped waiting
      co_return Unexpected{fmt::format("{}: the gateway ended the command before its end ({})",
                                       socket_path_, ec == asio::error::eof ? "closed" : ec.message())};
    }
    std::string line;
    std::istream stream(&input_);
    std::getline(stream, line);
    const auto message = control::parse_gateway(line);
    if (message) {
      if (const auto* event = std::get_if<control::Event>(&*message)) {
        on_event(event->json);
        continue;
      }
      if (const auto* exit = std::get_if<control::Exit>(&*message)) co_return exit->code;
      if (const auto* refused = std::get_if<control::Refused>(&*message))
        co_return Unexpected{fmt::format("{}: the gateway refused the command: {}", socket_path_,
                                         refused->reason)};
    }
    co_return Unexpected{fmt::format("{}: unexpected answer \"{}\"", socket_path_,
                                     visible_text(line.substr(0, 80)))};
  }
}

}  // namespace tiltgate
