// The protocol-free pseudo-terminal server under both simulators: bytes both ways, the link,
// pacing, unplug and its lifetime with sends in flight. Single-threaded: the test pumps the
// io_context while it waits, always up to a deadline.
#include "serial/pty_bus_server.h"

#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <cerrno>
#include <fcntl.h>
#include <unistd.h>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <memory>

#include "serial/termios_settings.h"
#include "sim/support/emulated_timing.h"
#include "sim/support/raw_tty_client.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using namespace std::chrono_literals;
using tiltgate::test::RawTtyClient;
using tiltgate::test::run_until;
using tiltgate::test::ScratchDir;

namespace {

using Bytes = std::vector<std::uint8_t>;

// An echo device: every chunk it reads goes back after `delay`.
struct EchoBus {
  boost::asio::io_context io;
  ScratchDir dir{"tiltgate-pty-bus"};
  Bytes received;
  std::chrono::milliseconds delay{0};
  std::unique_ptr<PtyBusServer> server;  // last: gone before what its callbacks use

  explicit EchoBus(PtyBusServerOptions options = {}) {
    if (options.link_path.empty()) options.link_path = dir.path("ttyBUS");
    server = std::make_unique<PtyBusServer>(io, std::move(options),
                                            [this](std::span<const std::uint8_t> bytes) {
                                              received.insert(received.end(), bytes.begin(),
                                                              bytes.end());
                                              server->send_after(delay, Bytes(bytes.begin(),
                                                                              bytes.end()));
                                            });
    const auto started = server->start();
    REQUIRE_MESSAGE(started.has_value(), started.error());
  }
};

}  // namespace

TEST_CASE("bytes written on the slave reach the receiver and sends reach the slave") {
  EchoBus bus;
  RawTtyClient client(bus.io, bus.server->slave_path());
  client.send(Bytes{1, 2, 3, 0xFF});
  CHECK(client.first_bytes(4) == Bytes{1, 2, 3, 0xFF});
  CHECK(bus.received == Bytes{1, 2, 3, 0xFF});
  CHECK(bus.server->counters().bytes_received == 4);
  CHECK(run_until(bus.io, [&] { return bus.server->counters().bytes_sent == 4; }));
}

TEST_CASE("sends go out at their own times: a late one holds up no one else's") {
  boost::asio::io_context io;
  std::uint64_t completed = 0;
  PtyBusServer server(io, {}, [](std::span<const std::uint8_t>) {}, [&] { ++completed; });
  REQUIRE(server.start().has_value());
  RawTtyClient client(io, server.slave_path());
  server.send_after(50ms, Bytes{'a'});
  server.send(Bytes{'b', 'c'});  // due at once, before 'a'
  CHECK(client.first_bytes(3) == Bytes{'b', 'c', 'a'});
  CHECK(run_until(io, [&] { return completed == 2; }));
  CHECK(server.counters().sends_completed == 2);
  CHECK(server.counters().collisions == 0);
}

TEST_CASE("two paced sends that would be on the line at once collide and arrive broken") {
  test::skip_if_emulated("the two sends must overlap on the wire within 5 ms of each other");
  boost::asio::io_context io;
  PtyBusServerOptions options;
  options.pace_baud = 9600;  // 10 bits a byte: 1.04 ms each
  PtyBusServer server(io, options, [](std::span<const std::uint8_t>) {});
  REQUIRE(server.start().has_value());
  RawTtyClient client(io, server.slave_path());
  server.send_after(5ms, Bytes(10, 0x11));  // on the line from 5 to 15 ms
  server.send_after(10ms, Bytes(4, 0x22));  // from 10 to 14 ms: inside the first
  server.send_after(40ms, Bytes(2, 0x33));  // well after both
  CHECK(client.first_bytes(16) == [] {
    Bytes expected(4, 0xDD);                // the second, broken, ends first
    expected.insert(expected.end(), 10, 0xEE);  // then the first, broken
    expected.insert(expected.end(), 2, 0x33);   // the third as sent
    return expected;
  }());
  CHECK(server.counters().collisions == 1);
}

TEST_CASE("the link follows the slave over replug, replaces a stale link and goes on unplug") {
  ScratchDir dir("tiltgate-pty-bus");
  const std::string link = dir.path("ttyBUS");
  std::filesystem::create_symlink("/dev/null", link);  // left over from an earlier run
  EchoBus bus({link, std::nullopt, 10});
  CHECK(std::filesystem::read_symlink(link) == bus.server->slave_path());

  bus.server->unplug();
  CHECK_FALSE(bus.server->plugged());
  CHECK(bus.server->slave_path().empty());
  CHECK_FALSE(std::filesystem::exists(std::filesystem::symlink_status(link)));

  REQUIRE(bus.server->replug().has_value());
  CHECK(bus.server->plugged());
  CHECK(std::filesystem::read_symlink(link) == bus.server->slave_path());
  RawTtyClient client(bus.io, link);
  client.send(Bytes{42});
  CHECK(client.first_bytes(1) == Bytes{42});
}

TEST_CASE("a file at the link path that is not a link is refused and kept") {
  boost::asio::io_context io;
  ScratchDir dir("tiltgate-pty-bus");
  const std::string path = dir.path("not-a-link");
  { std::ofstream(path) << "keep me"; }
  {
    PtyBusServer server(io, {path, std::nullopt, 10}, [](std::span<const std::uint8_t>) {});
    const auto started = server.start();
    REQUIRE_FALSE(started.has_value());
    CHECK(started.error().find("not a symbolic link") != std::string::npos);
    CHECK_FALSE(server.plugged());
  }
  CHECK(std::filesystem::is_regular_file(path));
}

TEST_CASE("paced sends take at least their transmission time at the baud and bits per byte") {
  // 24 bytes at 2400 baud, 11 bits a byte: 110 ms. Only the lower bound is checked; a busy
  // machine can only make it longer.
  EchoBus bus({"", 2400, 11});
  RawTtyClient client(bus.io, bus.server->link_path());
  const Bytes request(24, 0x55);
  const auto sent = std::chrono::steady_clock::now();
  client.send(request);
  CHECK(client.first_bytes(request.size()) == request);
  CHECK(std::chrono::steady_clock::now() - sent >= 110ms);
}

TEST_CASE("unplug makes the slave side read as a lost adapter and drops later sends") {
  EchoBus bus;
  RawTtyClient client(bus.io, bus.server->link_path());
  client.send(Bytes{7});
  CHECK(client.first_bytes(1) == Bytes{7});
  // The client can read the echo before the loop has run the write's completion: wait for it,
  // or a busy machine unplugs first and the echo is never counted.
  REQUIRE(run_until(bus.io, [&] { return bus.server->counters().sends_completed == 1; }));
  bus.server->unplug();
  int error = 0;
  const ssize_t n = client.read_once(error);
  CHECK(n <= 0);
  if (n < 0) CHECK(error == EIO);
  bus.server->send(Bytes{8});  // nobody to send to: dropped
  run_until(bus.io, [] { return false; }, 50ms);
  CHECK(bus.server->counters().sends_completed == 1);
}

TEST_CASE("destroying the server with a send still waiting is safe") {
  EchoBus bus;
  bus.delay = 100ms;  // the echo waits on its timer
  RawTtyClient client(bus.io, bus.server->link_path());
  client.send(Bytes{1, 2});
  REQUIRE(run_until(bus.io, [&] { return bus.received.size() == 2; }));
  bus.server.reset();
  // The aborted handlers run now, after the server is gone.
  bus.io.restart();
  bus.io.run_for(150ms);
  CHECK(client.first_bytes(1, 50ms).empty());
}

TEST_CASE("a receiver may unplug the bus from inside its callback") {
  boost::asio::io_context io;
  std::unique_ptr<PtyBusServer> server;
  std::size_t calls = 0;
  server = std::make_unique<PtyBusServer>(io, PtyBusServerOptions{},
                                          [&](std::span<const std::uint8_t>) {
                                            ++calls;
                                            server->unplug();
                                          });
  REQUIRE(server->start().has_value());
  RawTtyClient client(io, server->slave_path());
  client.send(Bytes{1});
  CHECK(run_until(io, [&] { return calls == 1; }));
  CHECK_FALSE(server->plugged());
  run_until(io, [] { return false; }, 50ms);
  CHECK(calls == 1);
}

TEST_CASE("a server that listens at one baud rate hears nothing sent at another") {
  PtyBusServerOptions options;
  options.listen_baud = 19200;
  EchoBus bus(options);
  // The slave's settings are the pseudo-terminal's: any descriptor on it sets the rate.
  const int settings_fd = ::open(bus.server->slave_path().c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
  REQUIRE(settings_fd >= 0);
  RawTtyClient client(bus.io, bus.server->slave_path());

  REQUIRE(apply_raw_settings(settings_fd, 9600, Parity::none, 1).has_value());
  client.send(Bytes{1, 2, 3});
  CHECK(run_until(bus.io, [&] { return bus.server->counters().bytes_unheard == 3; }));
  CHECK(bus.received.empty());

  REQUIRE(apply_raw_settings(settings_fd, 19200, Parity::none, 1).has_value());
  client.send(Bytes{4, 5});
  CHECK(client.first_bytes(2) == Bytes{4, 5});
  CHECK(bus.received == Bytes{4, 5});
  ::close(settings_fd);
}
