// The control socket end to end inside one process: a ControlServer on a real Unix socket in
// front of a BusScheduler with the fake line (its own thread, as the gateway's event loop), and
// a command's GatewayCommand. The command's run is the test's runner, which works on the served
// bus as the engine does (a command's line, control/served_bus_line.h): its transactions reach
// the bus as it made them while the gateway's other bus keeps polling, its events come back in
// order and then its exit code; a stop, a command gone and a command that stops reading each
// stop the run; a tty the gateway does not own, a missing gateway, a stale and a live socket
// file are each told apart.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <atomic>
#include <fmt/format.h>
#include <sys/stat.h>
#include <thread>

#include "control/control_server.h"
#include "control/gateway_command.h"
#include "control/served_bus_line.h"
#include "line_scheduling/bus_scheduler.h"
#include "unit/support/fake_bus.h"
#include "unit/support/scratch_dir.h"
#include "unit/support/socket_gateway.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;

namespace {

// Whole once `size` bytes have come, fed in as many pieces as the line likes.
class FixedLengthReply final : public ReplyFramer {
 public:
  explicit FixedLengthReply(std::size_t size) : size_(size) {}
  void reset() override {
    received.clear();
    ++resets;
  }
  bool feed(std::span<const std::uint8_t> bytes) override {
    received.insert(received.end(), bytes.begin(), bytes.end());
    return received.size() >= size_;
  }
  std::vector<std::uint8_t> received;
  int resets = 0;

 private:
  std::size_t size_;
};

struct Ran {
  Expected<int, std::string> exit{0};
  std::vector<std::string> events;
};

// The command's side: connects for `port`, runs `request`, and gives every event and the exit.
Ran run_command(const SocketGateway& gateway, const std::string& port,
                const std::string& request = "{}") {
  asio::io_context io;
  auto command = GatewayCommand::connect(io.get_executor(), gateway.socket_path, port);
  REQUIRE_MESSAGE(command, (command ? std::string() : command.error().message));
  Ran ran;
  bool done = false;
  asio::co_spawn(
      io,
      [&]() -> asio::awaitable<void> {
        ran.exit = co_await (*command)->run(
            request, [&](const std::string& event) { ran.events.push_back(event); });
        done = true;
      },
      asio::detached);
  REQUIRE(run_until(io, [&] { return done; }));
  return ran;
}

asio::awaitable<void> pause(std::chrono::milliseconds time) {
  asio::steady_timer timer(co_await asio::this_coro::executor, time);
  co_await timer.async_wait(asio::use_awaitable);
}

// A raw connection that has said its version and asked for the gateway's bus.
asio::local::stream_protocol::socket greeted(asio::io_context& io, const std::string& path) {
  asio::local::stream_protocol::socket raw(io);
  raw.connect(asio::local::stream_protocol::endpoint(path));
  asio::write(raw, asio::buffer(std::string("version 3 test\nhello /dev/ttyFAKE0\n")));
  asio::streambuf answer;
  asio::read_until(raw, answer, '\n');
  asio::read_until(raw, answer, '\n');
  return raw;
}

}  // namespace

TEST_CASE("control socket: a command's transaction goes out on the gateway's bus, and its events come back in order, then its exit code") {
  SocketGateway gateway;
  std::vector<std::uint8_t> whole;
  std::optional<LineError> short_error;
  std::size_t short_received = 0;
  std::string asked;
  gateway.runner = [&](std::string request, ServedBus bus, WriteOrigin by,
                       std::function<void(std::string)> emit,
                       CommandStop&) -> asio::awaitable<int> {
    asked = request;
    ServedBusLine line(std::move(bus), std::move(by));
    FixedLengthReply framer(3);
    // Named, not a temporary in the co_await: g++ 12 mishandles such a temporary.
    LineRequest first{{0x00, 0xDF, 0x04}, 0, &framer, 40ms, 0, 5ms};
    const auto done = co_await line.transact(std::move(first));
    whole = framer.received;
    emit(std::string(done ? "{\"n\":1}" : "{\"n\":-1}"));
    // A reply the command's framer never takes as whole is the command's time-out.
    FixedLengthReply wants_more(4);
    LineRequest second{{0x01}, 0, &wants_more, 40ms, 0, 0ms};
    const auto short_reply = co_await line.transact(std::move(second));
    if (!short_reply) short_error = short_reply.error();
    short_received = wants_more.received.size();
    emit(std::string("{\"n\":2}"));
    co_return 3;
  };
  const Ran ran = run_command(gateway, "/dev/ttyFAKE0", "{\"command\":\"raw\"}");
  REQUIRE(ran.exit);
  CHECK(*ran.exit == 3);
  CHECK(ran.events == std::vector<std::string>{"{\"n\":1}", "{\"n\":2}"});
  CHECK(asked == "{\"command\":\"raw\"}");
  CHECK(whole == std::vector<std::uint8_t>{0xA0, 0xA1, 0xA2});
  REQUIRE(gateway.sent.size() == 2);
  CHECK(gateway.sent[0].bytes == std::vector<std::uint8_t>{0x00, 0xDF, 0x04});
  CHECK(gateway.sent[0].timeout == 40ms);
  CHECK(gateway.sent[0].retries == 0);
  CHECK(gateway.sent[0].settle == 5ms);
  CHECK(short_error == LineError::timeout);
  CHECK(short_received == 3);
}

TEST_CASE("control socket: each attempt of a command's transaction is a turn of its own on the gateway's bus") {
  SocketGateway gateway;
  std::optional<LineError> error;
  std::uint64_t attempts = 0;
  gateway.runner = [&](std::string, ServedBus bus, WriteOrigin by, std::function<void(std::string)>,
                       CommandStop&) -> asio::awaitable<int> {
    ServedBusLine line(std::move(bus), std::move(by));
    FixedLengthReply never_whole(10);
    LineRequest request{{0x01}, 0, &never_whole, 30ms, 2, 0ms};
    request.late_guard = 450ms;  // a bus's usual guard
    const auto done = co_await line.transact(request);
    if (!done) error = done.error();
    attempts = line.stats().attempts;
    co_return 1;
  };
  const Ran ran = run_command(gateway, "/dev/ttyFAKE0");
  CHECK(error == LineError::timeout);
  // Three attempts, each sent once, so the gateway polls its sensors between them; and after a
  // silence the gateway's bus is held only briefly, whatever the command's own guard.
  REQUIRE(gateway.sent.size() == 3);
  for (const LineRequest& sent : gateway.sent) {
    CHECK(sent.retries == 0);
    CHECK(sent.timeout == 30ms);
    REQUIRE(sent.late_guard.has_value());
    CHECK(*sent.late_guard <= kMaxCommandLateGuard);
  }
  CHECK(attempts == 3);
}

TEST_CASE("control socket: while a command's run waits between steps, the gateway's other bus keeps polling") {
  SocketGateway gateway;
  int polls_meanwhile = -1;
  gateway.runner = [&](std::string, ServedBus, WriteOrigin, std::function<void(std::string)> emit,
                       CommandStop&) -> asio::awaitable<int> {
    const int before = gateway.other_polls;
    co_await pause(200ms);  // e.g. watch's interval between rounds
    polls_meanwhile = gateway.other_polls - before;
    emit(std::string("{}"));
    co_return 0;
  };
  const Ran ran = run_command(gateway, "/dev/ttyFAKE0");
  REQUIRE(ran.exit);
  // Every 10 ms: a run that held the gateway's event loop would let it poll none.
  CHECK(polls_meanwhile >= 5);
}

TEST_CASE("control socket: a sensor a command moved is polled at its new address") {
  SocketGateway gateway;
  std::optional<std::string> followed;
  std::optional<std::string> nobody{"unset"};
  gateway.runner = [&](std::string, ServedBus bus, WriteOrigin by, std::function<void(std::string)>,
                       CommandStop&) -> asio::awaitable<int> {
    ServedBusLine line(std::move(bus), std::move(by));
    followed = line.follow(223, 7);
    nobody = line.follow(100, 8);
    co_return 0;
  };
  const Ran ran = run_command(gateway, "line1");  // by name
  REQUIRE(ran.exit);
  REQUIRE(followed);
  CHECK(*followed == "boom");
  CHECK(gateway.sensor->driver->state().bus_address == 7);
  CHECK_FALSE(nobody.has_value());
}

TEST_CASE("control socket: the command's stop ends its run, which still says its exit code") {
  SocketGateway gateway;
  std::atomic<bool> line_stopped{false};
  gateway.runner = [&](std::string, ServedBus, WriteOrigin, std::function<void(std::string)> emit,
                       CommandStop& stop) -> asio::awaitable<int> {
    stop.on_request = [&] { line_stopped = true; };
    emit(std::string("{\"running\":true}"));
    for (int i = 0; i < 500 && !stop.requested; ++i) co_await pause(10ms);
    stop.on_request = nullptr;
    co_return stop.requested ? 0 : 7;
  };
  asio::io_context io;
  auto command = GatewayCommand::connect(io.get_executor(), gateway.socket_path, "/dev/ttyFAKE0");
  REQUIRE(command);
  std::optional<Expected<int, std::string>> exit;
  asio::co_spawn(
      io,
      [&]() -> asio::awaitable<void> {
        exit = co_await (*command)->run("{}", [&](const std::string&) { (*command)->stop(); });
      },
      asio::detached);
  REQUIRE(run_until(io, [&] { return exit.has_value(); }));
  REQUIRE(*exit);
  CHECK(**exit == 0);
  CHECK(line_stopped);
}

TEST_CASE("control socket: a command that goes away mid-run stops it") {
  SocketGateway gateway;
  std::atomic<bool> stopped{false};
  std::atomic<bool> started{false};
  gateway.runner = [&](std::string, ServedBus, WriteOrigin, std::function<void(std::string)>,
                       CommandStop& stop) -> asio::awaitable<int> {
    started = true;
    for (int i = 0; i < 500 && !stop.requested; ++i) co_await pause(10ms);
    stopped = stop.requested;
    co_return 0;
  };
  {
    asio::io_context io;
    auto raw = greeted(io, gateway.socket_path);
    asio::write(raw, asio::buffer(std::string("run {}\n")));
    const auto deadline = std::chrono::steady_clock::now() + 5s;
    while (!started && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);
    REQUIRE(started);
  }  // closed
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (!stopped && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);
  CHECK(stopped);
}

TEST_CASE("control socket: a command that stops reading its events is stopped, not queued for without end") {
  SocketGateway gateway;
  std::atomic<int> emitted{0};
  std::atomic<bool> stopped{false};
  gateway.runner = [&](std::string, ServedBus, WriteOrigin, std::function<void(std::string)> emit,
                       CommandStop& stop) -> asio::awaitable<int> {
    const std::string big(1024 * 1024, 'x');
    for (int i = 0; i < 200 && !stop.requested; ++i) {
      emit(fmt::format("\"{}\"", big));
      ++emitted;
      co_await pause(1ms);
    }
    stopped = stop.requested;
    co_return 0;
  };
  asio::io_context io;
  auto raw = greeted(io, gateway.socket_path);
  asio::write(raw, asio::buffer(std::string("run {}\n")));  // and never reads again
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (!stopped && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);
  CHECK(stopped);
  // What the writer may queue (16 MiB), and what the socket's buffers took besides.
  CHECK(emitted < 40);
}

TEST_CASE("control socket: a run before the bus is asked for is refused") {
  SocketGateway gateway;
  asio::io_context io;
  asio::local::stream_protocol::socket raw(io);
  raw.connect(asio::local::stream_protocol::endpoint(gateway.socket_path));
  asio::write(raw, asio::buffer(std::string("version 3 test\nrun {}\n")));
  asio::streambuf answer;
  std::istream lines(&answer);
  std::string line;
  asio::read_until(raw, answer, '\n');
  std::getline(lines, line);
  asio::read_until(raw, answer, '\n');
  std::getline(lines, line);
  CHECK(line == "error ask for a bus first (hello PORT)");
}

TEST_CASE("control socket: a tty the gateway does not own, and no gateway at all, are told apart") {
  SocketGateway gateway;
  asio::io_context io;
  auto other = GatewayCommand::connect(io.get_executor(), gateway.socket_path, "/dev/ttyUSB7");
  REQUIRE_FALSE(other);
  CHECK(other.error().kind == GatewayCommand::ConnectError::not_served);
  CHECK(other.error().message.find("line1 on /dev/ttyFAKE0") != std::string::npos);

  auto none = GatewayCommand::connect(io.get_executor(), gateway.dir.path("nothing.sock"), "/dev/ttyFAKE0");
  REQUIRE_FALSE(none);
  CHECK(none.error().kind == GatewayCommand::ConnectError::no_gateway);
}

TEST_CASE("control socket: a device server's port is found however the command names it") {
  SocketGateway gateway("rfc2217://Moxa-3.plant.local:4001");
  asio::io_context io;
  for (const char* port : {"rfc2217://Moxa-3.plant.local:4001", "tcp://moxa-3.PLANT.local:4001"}) {
    CAPTURE(port);
    auto line = GatewayCommand::connect(io.get_executor(), gateway.socket_path, port);
    REQUIRE_MESSAGE(line, (line ? std::string() : line.error().message));
    CHECK((*line)->bus().name == "line1");
  }
  auto other = GatewayCommand::connect(io.get_executor(), gateway.socket_path,
                                       "tcp://moxa-3.plant.local:4002");
  REQUIRE_FALSE(other);
  CHECK(other.error().kind == GatewayCommand::ConnectError::not_served);
}

TEST_CASE("control socket: the socket file is for owner and group only, and a live one is not taken over") {
  SocketGateway gateway;
  struct stat st {};
  REQUIRE(::stat(gateway.socket_path.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0660);

  asio::io_context io;
  BusScheduler scheduler{io.get_executor(), gateway.line, "line1"};
  ControlServer second{io.get_executor(), gateway.socket_path,
                       {{bus_on("/dev/ttyFAKE0"), lent(scheduler)}}, gateway.runner};
  const auto refused = second.start();
  REQUIRE_FALSE(refused);
  CHECK(refused.error().find("another gateway is listening") != std::string::npos);
}

TEST_CASE("control socket: a socket file left by a killed gateway is replaced") {
  ScratchDir dir{"tiltgate-control"};
  const std::string path = dir.path("control.sock");
  asio::io_context io;
  {
    // Bound and closed without removing the file, as a SIGKILLed gateway leaves it.
    asio::local::stream_protocol::acceptor stale(io, asio::local::stream_protocol::endpoint(path));
  }
  REQUIRE(std::filesystem::exists(path));
  FakeLine line{io.get_executor()};
  BusScheduler scheduler{io.get_executor(), line, "line1"};
  ControlServer server{io.get_executor(), path, {{bus_on("/dev/ttyFAKE0"), lent(scheduler)}}, {}};
  CHECK(server.start());
  server.stop();
  CHECK_FALSE(std::filesystem::exists(path));  // removed on stop
}

TEST_CASE("control socket: a garbled message is refused and ends that session only") {
  SocketGateway gateway;
  asio::io_context io;
  asio::local::stream_protocol::socket raw(io);
  raw.connect(asio::local::stream_protocol::endpoint(gateway.socket_path));
  asio::write(raw, asio::buffer(std::string("version 3 test\ntransact nonsense\n")));
  asio::streambuf answer;
  asio::read_until(raw, answer, '\n');
  std::istream lines(&answer);
  std::string line;
  std::getline(lines, line);  // the gateway's version
  CHECK(line.rfind("version 3 ", 0) == 0);
  asio::read_until(raw, answer, '\n');
  std::getline(lines, line);
  CHECK(line.rfind("error malformed message", 0) == 0);
  // Everyone else is still served.
  auto fine = GatewayCommand::connect(io.get_executor(), gateway.socket_path, "/dev/ttyFAKE0");
  CHECK(fine);
}
