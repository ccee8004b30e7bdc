#include "control/control_server.h"

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fmt/format.h>
#include <istream>
#include <spdlog/spdlog.h>
#include <sys/stat.h>
#include <unistd.h>
#include <utility>

#include "control/control_protocol.h"
#include "control/control_session.h"
#include "control/peer_identity.h"
#include "device_server/port_url.h"

namespace tiltgate {

namespace asio = boost::asio;
using local = asio::local::stream_protocol;

namespace {

// The same tty however it is named: /dev/serial/by-id/... and /dev/ttyUSB0 compare equal; the
// same device server port however it is reached: its host without case and its TCP port,
// tcp:// or rfc2217:// (the port takes one client: the gateway's).
std::string canonical_port(const std::string& port) {
  if (const auto address = parse_port(port); address && address->over_network()) {
    std::string endpoint = address->endpoint();
    std::transform(endpoint.begin(), endpoint.end(), endpoint.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return endpoint;
  }
  std::error_code ec;
  const auto path = std::filesystem::weakly_canonical(port, ec);
  return ec ? port : path.string();
}

// Whether a gateway is listening on `path` now.
bool someone_listens(const std::string& path, asio::any_io_executor executor) {
  local::socket probe(executor);
  boost::system::error_code ec;
  probe.connect(local::endpoint(path), ec);
  return !ec;
}

// Takes the message formatted: g++ 12 destroys a temporary in a co_await expression twice, so
// callers format into a named string first.
asio::awaitable<bool> send(local::socket& socket, std::string line) {
  line += '\n';
  boost::system::error_code ec;
  co_await asio::async_write(socket, asio::buffer(line),
                             asio::redirect_error(asio::use_awaitable, ec));
  co_return !ec;
}

}  // namespace

ControlServer::ControlServer(asio::any_io_executor executor, std::string path,
                             std::vector<ServedBus> buses, CommandRunner runner)
    : executor_(executor),
      path_(std::move(path)),
      buses_(std::move(buses)),
      runner_(std::move(runner)),
      acceptor_(executor) {}

ControlServer::~ControlServer() { stop(); }

Expected<Done, std::string> ControlServer::start() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path folder = fs::path(path_).parent_path();
  if (!folder.empty() && !fs::exists(folder, ec)) {
    fs::create_directories(folder, ec);
    if (ec) return Unexpected{fmt::format("cannot create {}: {}", folder.string(), ec.message())};
  }
  if (fs::exists(fs::symlink_status(path_, ec))) {
    if (someone_listens(path_, executor_))
      return Unexpected{fmt::format("{}: another gateway is listening there", path_)};
    if (!fs::is_socket(fs::symlink_status(path_, ec)))
      return Unexpected{fmt::format("{}: exists and is not a socket; not replacing it", path_)};
    fs::remove(path_, ec);  // stale: its gateway was killed
  }
  boost::system::error_code error;
  acceptor_.open(local(), error);
  if (!error) bind_for_owner_and_group(error);
  if (!error) acceptor_.listen(asio::socket_base::max_listen_connections, error);
  if (error) {
    acceptor_.close();
    return Unexpected{fmt::format("cannot listen on {}: {}", path_, error.message())};
  }
  listening_ = true;
  spawn(accept_loop());
  return Done{};
}

void ControlServer::bind_for_owner_and_group(boost::system::error_code& error) {
  // Connecting lets a program move sensors and change their settings: owner and group only,
  // from the instant the file exists (a chmod after bind leaves a moment when anyone may
  // connect). bind() makes the file 0777 less the umask, so the umask is narrowed around it.
  // The umask is the process's: the other threads then (the Modbus TCP connections' and
  // libmosquitto's) make no files, and one that did would only get fewer rights.
  const mode_t before = ::umask(0117);
  acceptor_.bind(local::endpoint(path_), error);
  ::umask(before);
}

void ControlServer::spawn(asio::awaitable<void> work) {
  ++coroutines_;
  asio::co_spawn(executor_, std::move(work), [this](std::exception_ptr failure) {
    --coroutines_;
    // A session that failed ends alone (its line records what it carried and frees what it
    // held as it goes); said once, so that it is not a silence.
    if (failure) {
      try {
        std::rethrow_exception(failure);
      } catch (const std::exception& e) {
        spdlog::error("control socket: a command's session failed: {}", e.what());
      } catch (...) {
        spdlog::error("control socket: a command's session failed");
      }
    }
  });
}

void ControlServer::stop() {
  if (!listening_) return;
  listening_ = false;
  boost::system::error_code ec;
  acceptor_.close(ec);
  for (auto& weak : sessions_)
    if (auto socket = weak.lock()) socket->close(ec);
  sessions_.clear();
  std::error_code removed;
  std::filesystem::remove(path_, removed);
}

asio::awaitable<void> ControlServer::accept_loop() {
  while (listening_) {
    boost::system::error_code ec;
    local::socket socket = co_await acceptor_.async_accept(asio::redirect_error(asio::use_awaitable, ec));
    if (ec) {
      if (!listening_) co_return;
      continue;
    }
    std::erase_if(sessions_, [](const auto& weak) { return weak.expired(); });
    if (sessions_.size() >= kMaxSessions) {
      const std::string refusal =
          control::format(control::GatewayMessage{control::Refused{fmt::format(
              "the gateway already serves {} commissioning commands; try again later",
              kMaxSessions)}}) + "\n";
      asio::write(socket, asio::buffer(refusal), ec);
      continue;
    }
    spawn(session(std::move(socket)));
  }
}

ControlServer::ServedBus* ControlServer::find_bus(const std::string& port_or_name) {
  const std::string wanted = canonical_port(port_or_name);
  for (ServedBus& bus : buses_)
    if (bus.config.name == port_or_name || canonical_port(bus.config.port) == wanted) return &bus;
  return nullptr;
}

std::string ControlServer::bus_list() const {
  std::string list;
  for (const ServedBus& bus : buses_)
    list += fmt::format("{}{} on {}", list.empty() ? "" : ", ", bus.config.name, bus.config.port);
  return list.empty() ? "none" : list;
}

asio::awaitable<void> ControlServer::session(local::socket accepted) {
  auto socket = std::make_shared<local::socket>(std::move(accepted));
  sessions_.push_back(socket);
  asio::streambuf input(control::kMaxLine);
  {
    // Who connected, for the log line of a sensor it moves and the audit trail.
    ControlSession::Setup setup{
        [this](const std::string& port) -> const ServedBus* { return find_bus(port); },
        [this] { return bus_list(); },
        WriteOrigin{"control socket", peer_identity(socket->native_handle())}, runner_};
    ControlSession session(*socket, input, std::move(setup));
    while (listening_) {
      boost::system::error_code ec;
      co_await asio::async_read_until(*socket, input, '\n',
                                      asio::redirect_error(asio::use_awaitable, ec));
      if (ec) break;  // gone, closed by stop(), or a line longer than kMaxLine
      std::string line;
      std::istream stream(&input);
      std::getline(stream, line);
      bool done = false;
      std::string reply = co_await session.answer(line, done);
      if (!co_await send(*socket, std::move(reply)) || done) break;
    }
  }  // the session's line records what is pending and polls again what it held
  boost::system::error_code ignored;
  socket->close(ignored);
}

}  // namespace tiltgate
