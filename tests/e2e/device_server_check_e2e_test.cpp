// build/tiltgate check and scan on buses behind serial device servers: a URL in error is
// printed at its line, a good one passes without a connection or a name lookup, and
// scan --baud auto over raw TCP is refused before anything is opened.
#include <doctest/doctest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <string>

#include "e2e/support/gateway_process.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

// A Rieker bus on `port` (its `port` key on line 6) and one sensor.
std::string config_on(const std::string& port) {
  return "[server]\nport = 5020\n\n[[bus]]\nname = \"line1\"\nport = \"" + port +
         "\"\nprotocol = \"rieker\"\n\n[[sensor]]\nname = \"boom\"\nbus = \"line1\"\n"
         "model = \"h6\"\naddress = 223\nunit_id = 1\n";
}

// A listening loopback socket nothing is expected to connect to.
class Listener {
 public:
  Listener() {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    REQUIRE(fd_ >= 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    REQUIRE(::bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0);
    REQUIRE(::listen(fd_, 8) == 0);
    socklen_t length = sizeof address;
    REQUIRE(::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) == 0);
    port_ = ntohs(address.sin_port);
  }
  ~Listener() { ::close(fd_); }
  Listener(const Listener&) = delete;
  Listener& operator=(const Listener&) = delete;

  std::uint16_t port() const { return port_; }
  // Whether a connection was made: the kernel completes the handshake into the backlog
  // whether or not the client is still there, so a connect that happened is still here.
  bool connected() const {
    const int client = ::accept(fd_, nullptr, nullptr);
    if (client < 0) {
      CHECK((errno == EAGAIN || errno == EWOULDBLOCK));
      return false;
    }
    ::close(client);
    return true;
  }

 private:
  int fd_ = -1;
  std::uint16_t port_ = 0;
};

}  // namespace

TEST_CASE("check prints a device server URL's error at its line") {
  TempDir dir;
  const auto bad = dir.write("bad.toml", config_on("tcp://192.168.1.20:0"));
  const auto checked = run_tiltgate({"check", "--config", bad.string()});
  CHECK(checked.exit_code == 1);
  CHECK_MESSAGE(checked.err.find(bad.string() +
                                 ":6:1: bus[0].port: the port 0 is out of range, expected "
                                 "1..65535\n") != std::string::npos,
                checked.err);
  const auto scheme = dir.write("scheme.toml", config_on("ssh://192.168.1.20:4001"));
  const auto unknown = run_tiltgate({"check", "--config", scheme.string()});
  CHECK(unknown.exit_code == 1);
  CHECK_MESSAGE(unknown.err.find(scheme.string() + ":6:1: bus[0].port: unknown scheme \"ssh://\"") !=
                    std::string::npos,
                unknown.err);
}

TEST_CASE("check passes a device server's URL without connecting or resolving its name") {
  TempDir dir;
  Listener server;
  const auto listening =
      dir.write("raw.toml", config_on("tcp://127.0.0.1:" + std::to_string(server.port())));
  const auto checked = run_tiltgate({"check", "--config", listening.string()});
  CHECK_MESSAGE(checked.exit_code == 0, checked.err);
  CHECK_FALSE(server.connected());
  // A name no resolver knows (RFC 6761's .invalid) is only looked up when the gateway starts.
  const auto named = dir.write("named.toml", config_on("rfc2217://moxa.invalid:4001"));
  const auto unresolved = run_tiltgate({"check", "--config", named.string()});
  CHECK_MESSAGE(unresolved.exit_code == 0, unresolved.err);
}

TEST_CASE("scan --baud auto over raw TCP is refused with the reason, before connecting") {
  Listener server;
  const std::string port = "tcp://127.0.0.1:" + std::to_string(server.port());
  const auto scan = run_tiltgate({"scan", "--port", port, "--protocol", "rieker", "--baud",
                                  "auto", "--control-socket", "/nonexistent/control.sock"});
  CHECK(scan.exit_code == 2);
  CHECK_MESSAGE(scan.err.find("tiltgate scan: --baud auto: not over tcp:// (raw TCP cannot "
                              "change the device server's rate") != std::string::npos,
                scan.err);
  CHECK_FALSE(server.connected());
}
