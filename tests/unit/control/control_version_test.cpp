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

#include "control/remote_line.h"
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

}  // namespace

TEST_CASE("control socket: a command of protocol 1 (hello first) gets one line naming both versions, then the end") {
  SocketGateway gateway;
  const auto lines = answers_to(gateway.socket_path, "hello /dev/ttyFAKE0");
  REQUIRE(lines.size() == 1);
  INFO(lines[0]);
  CHECK(lines[0].starts_with("version 2 "));  // not "error": protocol 1 shows it as it is
  CHECK(lines[0].find("speaks control protocol 2") != std::string::npos);
  CHECK(lines[0].find("speaks control protocol 1") != std::string::npos);
}

TEST_CASE("control socket: a command of another protocol is told both versions, and the session ends") {
  SocketGateway gateway;
  const auto lines = answers_to(gateway.socket_path, "version 3 9.9.9");
  REQUIRE(lines.size() == 1);
  INFO(lines[0]);
  CHECK(lines[0].find("(tiltgate 9.9.9) speaks control protocol 3") != std::string::npos);
  CHECK(lines[0].find("speaks control protocol 2") != std::string::npos);
  // The same version is answered with the gateway's own, and the session goes on.
  asio::io_context io;
  auto line = RemoteLine::connect(io.get_executor(), gateway.socket_path, "/dev/ttyFAKE0");
  CHECK(line.has_value());
}

TEST_CASE("control socket: a gateway of protocol 1 is named as such by a newer command, which does not hang") {
  ScratchDir dir{"tiltgate-control-old"};
  const std::string path = dir.path("old.sock");
  asio::io_context io;
  asio::local::stream_protocol::acceptor acceptor(io, asio::local::stream_protocol::endpoint(path));
  // What a gateway of protocol 1 answers a line it cannot read, and then it closes.
  std::thread old_gateway([&] {
    asio::local::stream_protocol::socket socket(io);
    acceptor.accept(socket);
    asio::streambuf input;
    asio::read_until(socket, input, '\n');
    asio::write(socket, asio::buffer(std::string("error malformed message \"version 2 0.1.0\"\n")));
  });
  asio::io_context command;
  auto line = RemoteLine::connect(command.get_executor(), path, "/dev/ttyFAKE0");
  old_gateway.join();
  REQUIRE_FALSE(line.has_value());
  INFO(line.error().message);
  CHECK(line.error().message.find("speaks control protocol 1") != std::string::npos);
  CHECK(line.error().message.find("speaks control protocol 2") != std::string::npos);
}
