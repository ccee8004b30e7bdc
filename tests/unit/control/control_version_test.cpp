// The control socket's version line (control/control_protocol.h): a command and a gateway of
// different protocols end with one line naming both, never a hang.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/write.hpp>
#include <istream>
#include <string>
#include <thread>
#include <vector>

#include "control/gateway_command.h"
#include "unit/support/scratch_dir.h"
#include "unit/support/socket_gateway.h"

using namespace tiltgate;
using namespace tiltgate::test;
namespace asio = boost::asio;

namespace {

// One line said on a fresh connection to `path`, and the lines answered until the gateway
// closes it (or 2 s pass).
std::vector<std::string> answers_to(const std::string& path, const std::string& said) {
  asio::io_context io;
  asio::local::stream_protocol::socket socket(io);
  socket.connect(asio::local::stream_protocol::endpoint(path));
  asio::write(socket, asio::buffer(said + "\n"));
  std::vector<std::string> lines;
  asio::streambuf input;
  boost::system::error_code ec;
  while (!ec && lines.size() < 4) {
    asio::read_until(socket, input, '\n', ec);
    if (ec) break;
    std::istream stream(&input);
    std::string line;
    std::getline(stream, line);
    lines.push_back(line);
  }
  return lines;
}

// A newer command connecting to an older gateway that answers its first line with `answer`
// and closes.
Expected<std::unique_ptr<GatewayCommand>, GatewayCommand::ConnectError> connect_to_old_gateway(
    const std::string& answer) {
  ScratchDir dir{"tiltgate-control-old"};
  const std::string path = dir.path("old.sock");
  asio::io_context io;
  asio::local::stream_protocol::acceptor acceptor(io, asio::local::stream_protocol::endpoint(path));
  std::thread old_gateway([&] {
    asio::local::stream_protocol::socket socket(io);
    acceptor.accept(socket);
    asio::streambuf input;
    asio::read_until(socket, input, '\n');
    asio::write(socket, asio::buffer(answer));
  });
  // Outlives the call: a command that did connect keeps its socket on it.
  static asio::io_context command;
  auto line = GatewayCommand::connect(command.get_executor(), path, "/dev/ttyFAKE0");
  old_gateway.join();
  return line;
}

}  // namespace

TEST_CASE("control socket: a command of protocol 1 (hello first) gets one line naming both versions, then the end") {
  SocketGateway gateway;
  const auto lines = answers_to(gateway.socket_path, "hello /dev/ttyFAKE0");
  REQUIRE(lines.size() == 1);
  INFO(lines[0]);
  CHECK(lines[0].starts_with("version 3 "));  // not "error": protocol 1 shows it as it is
  CHECK(lines[0].find("speaks control protocol 3") != std::string::npos);
  CHECK(lines[0].find("speaks control protocol 1") != std::string::npos);
}

TEST_CASE("control socket: a command of another protocol is told both versions, and the session ends") {
  SocketGateway gateway;
  // The previous release's command, which relayed transactions (protocol 2).
  const auto lines = answers_to(gateway.socket_path, "version 2 0.0.9");
  REQUIRE(lines.size() == 1);
  INFO(lines[0]);
  CHECK(lines[0].find("(tiltgate 0.0.9) speaks control protocol 2") != std::string::npos);
  CHECK(lines[0].find("speaks control protocol 3") != std::string::npos);
  // The same version is answered with the gateway's own, and the session goes on.
  asio::io_context io;
  auto line = GatewayCommand::connect(io.get_executor(), gateway.socket_path, "/dev/ttyFAKE0");
  CHECK(line.has_value());
}

TEST_CASE("control socket: a gateway of protocol 1 is named as such by a newer command, which does not hang") {
  // What a gateway of protocol 1 answers a line it cannot read, and then it closes.
  const auto line = connect_to_old_gateway("error malformed message \"version 3 0.1.0\"\n");
  REQUIRE_FALSE(line.has_value());
  INFO(line.error().message);
  CHECK(line.error().message.find("speaks control protocol 1") != std::string::npos);
  CHECK(line.error().message.find("speaks control protocol 3") != std::string::npos);
}

TEST_CASE("control socket: a gateway of the previous protocol answers with its own mismatch line, which a newer command shows whole") {
  // What a gateway of protocol 2 answers a version it does not speak, and then it closes.
  const auto line = connect_to_old_gateway(
      "version 2 0.0.9: this gateway (tiltgate 0.0.9) speaks control protocol 2, this command "
      "(tiltgate 0.1.0) speaks control protocol 3: run the tiltgate of the gateway's own version\n");
  REQUIRE_FALSE(line.has_value());
  INFO(line.error().message);
  CHECK(line.error().kind == GatewayCommand::ConnectError::failed);
  CHECK(line.error().message.find("speaks control protocol 2") != std::string::npos);
  CHECK(line.error().message.find("speaks control protocol 3") != std::string::npos);
}
