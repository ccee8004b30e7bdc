// The control socket end to end inside one process: a ControlServer on a real Unix socket in
// front of a BusScheduler with the fake line (its own thread, as the gateway's event loop), and
// a command's RemoteLine. A transaction reaches the bus as the command sent it and the reply
// is framed by the command's framer, while the gateway's other bus keeps polling however long
// the command thinks; a sensor the command moved is followed; a tty the gateway does not own, a
// missing gateway, a stale and a live socket file are each told apart.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/read_until.hpp>
#include <boost/asio/streambuf.hpp>
#include <boost/asio/write.hpp>
#include <atomic>
#include <future>
#include <sys/stat.h>
#include <thread>

#include "audit/audit_trail.h"
#include "line_scheduling/bus_scheduler.h"
#include "control/control_server.h"
#include "control/remote_line.h"
#include "unit/support/fake_bus.h"
#include "unit/support/socket_gateway.h"
#include "unit/support/scratch_dir.h"

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

// A slow command: each chunk is thought over for `think` before the framer is asked; how
// often the gateway's other bus was polled meanwhile is kept.
class SlowReply final : public ReplyFramer {
 public:
  SlowReply(std::size_t size, std::chrono::milliseconds think, const std::atomic<int>& polls)
      : size_(size), think_(think), polls_(polls) {}
  void reset() override { received_ = 0; }
  bool feed(std::span<const std::uint8_t> bytes) override {
    const int before = polls_;
    std::this_thread::sleep_for(think_);
    polls_while_thinking.push_back(polls_ - before);
    received_ += bytes.size();
    return received_ >= size_;
  }
  std::vector<int> polls_while_thinking;

 private:
  std::size_t size_;
  std::chrono::milliseconds think_;
  const std::atomic<int>& polls_;
  std::size_t received_ = 0;
};

// Runs `line.transact(request)` on a command's own event loop.
Expected<Done, LineError> transact(RemoteLine& line, asio::io_context& io, LineRequest request) {
  std::optional<Expected<Done, LineError>> result;
  asio::co_spawn(
      io, [&]() -> asio::awaitable<void> { result = co_await line.transact(request); },
      asio::detached);
  REQUIRE(run_until(io, [&] { return result.has_value(); }));
  return *result;
}

}  // namespace

TEST_CASE("control socket: a command's transaction goes out on the gateway's bus, framed by the command") {
  SocketGateway gateway;
  asio::io_context io;
  auto line = RemoteLine::connect(io.get_executor(), gateway.socket_path, "/dev/ttyFAKE0");
  REQUIRE(line);
  CHECK((*line)->bus().name == "line1");
  CHECK((*line)->bus().baud == 19200);

  FixedLengthReply framer(3);
  const auto done = transact(**line, io, LineRequest{{0x00, 0xDF, 0x04}, 0, &framer, 40ms, 0, 5ms});
  CHECK(done.has_value());
  CHECK(framer.received == std::vector<std::uint8_t>{0xA0, 0xA1, 0xA2});
  CHECK(framer.resets == 1);
  REQUIRE(gateway.sent.size() == 1);
  CHECK(gateway.sent[0].bytes == std::vector<std::uint8_t>{0x00, 0xDF, 0x04});
  CHECK(gateway.sent[0].timeout == 40ms);
  CHECK(gateway.sent[0].retries == 0);
  CHECK(gateway.sent[0].settle == 5ms);

  // A reply the command's framer never takes as whole is the command's time-out.
  FixedLengthReply wants_more(4);
  const auto short_reply = transact(**line, io, LineRequest{{0x01}, 0, &wants_more, 40ms, 0, 0ms});
  CHECK(short_reply.error() == LineError::timeout);
  CHECK(wants_more.received.size() == 3);
}

TEST_CASE("control socket: each attempt of a command's transaction is a turn of its own on the gateway's bus") {
  SocketGateway gateway;
  asio::io_context io;
  auto line = RemoteLine::connect(io.get_executor(), gateway.socket_path, "/dev/ttyFAKE0");
  REQUIRE(line);
  FixedLengthReply never_whole(10);
  LineRequest request{{0x01}, 0, &never_whole, 30ms, 2, 0ms};
  request.late_guard = 450ms;  // a bus's usual guard
  const auto done = transact(**line, io, request);
  CHECK(done.error() == LineError::timeout);
  // Three attempts, each sent once, so the gateway polls its sensors between them; and after a
  // silence the gateway's bus is held only briefly, whatever the command's own guard.
  REQUIRE(gateway.sent.size() == 3);
  for (const LineRequest& sent : gateway.sent) {
    CHECK(sent.retries == 0);
    CHECK(sent.timeout == 30ms);
    REQUIRE(sent.late_guard.has_value());
    CHECK(*sent.late_guard <= kMaxCommandLateGuard);
  }
  CHECK((*line)->stats().attempts == 3);
}

TEST_CASE("control socket: while a command thinks over a chunk, the gateway's other bus keeps polling") {
  SocketGateway gateway;
  asio::io_context io;
  auto line = RemoteLine::connect(io.get_executor(), gateway.socket_path, "/dev/ttyFAKE0");
  REQUIRE(line);
  SlowReply framer(3, 80ms, gateway.other_polls);  // within the gateway's 100 ms wait
  const auto done = transact(**line, io, LineRequest{{0x00, 0xDF, 0x04}, 0, &framer, 10ms, 0});
  CHECK(done.has_value());
  REQUIRE(framer.polls_while_thinking.size() == 1);
  // Every 10 ms: a gateway that waited for the answer on its event loop would poll none.
  CHECK(framer.polls_while_thinking[0] >= 3);
}

TEST_CASE("control socket: a sensor a command moved is polled at its new address") {
  SocketGateway gateway;
  asio::io_context io;
  auto line = RemoteLine::connect(io.get_executor(), gateway.socket_path, "line1");  // by name
  REQUIRE(line);
  const auto followed = (*line)->follow(223, 7);
  REQUIRE(followed);
  CHECK(*followed == "line1/boom");
  CHECK(gateway.sensor->driver->state().bus_address == 7);
  const auto nobody = (*line)->follow(100, 8);
  REQUIRE(nobody);
  CHECK(nobody->empty());
}

TEST_CASE("control socket: a tty the gateway does not own, and no gateway at all, are told apart") {
  SocketGateway gateway;
  asio::io_context io;
  auto other = RemoteLine::connect(io.get_executor(), gateway.socket_path, "/dev/ttyUSB7");
  REQUIRE_FALSE(other);
  CHECK(other.error().kind == RemoteLine::ConnectError::not_served);
  CHECK(other.error().message.find("line1 on /dev/ttyFAKE0") != std::string::npos);

  auto none = RemoteLine::connect(io.get_executor(), gateway.dir.path("nothing.sock"), "/dev/ttyFAKE0");
  REQUIRE_FALSE(none);
  CHECK(none.error().kind == RemoteLine::ConnectError::no_gateway);
}

TEST_CASE("control socket: a device server's port is found however the command names it") {
  SocketGateway gateway("rfc2217://Moxa-3.plant.local:4001");
  asio::io_context io;
  for (const char* port : {"rfc2217://Moxa-3.plant.local:4001", "tcp://moxa-3.PLANT.local:4001"}) {
    CAPTURE(port);
    auto line = RemoteLine::connect(io.get_executor(), gateway.socket_path, port);
    REQUIRE_MESSAGE(line, (line ? std::string() : line.error().message));
    CHECK((*line)->bus().name == "line1");
  }
  auto other = RemoteLine::connect(io.get_executor(), gateway.socket_path,
                                   "tcp://moxa-3.plant.local:4002");
  REQUIRE_FALSE(other);
  CHECK(other.error().kind == RemoteLine::ConnectError::not_served);
}

TEST_CASE("control socket: the socket file is for owner and group only, and a live one is not taken over") {
  SocketGateway gateway;
  struct stat st {};
  REQUIRE(::stat(gateway.socket_path.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0660);

  asio::io_context io;
  BusScheduler scheduler{io.get_executor(), gateway.line, "line1"};
  ControlServer second{io.get_executor(), gateway.socket_path, {{bus_on("/dev/ttyFAKE0"), lent(scheduler)}}};
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
  ControlServer server{io.get_executor(), path, {{bus_on("/dev/ttyFAKE0"), lent(scheduler)}}};
  CHECK(server.start());
  server.stop();
  CHECK_FALSE(std::filesystem::exists(path));  // removed on stop
}

TEST_CASE("control socket: a garbled message is refused and ends that session only") {
  SocketGateway gateway;
  asio::io_context io;
  asio::local::stream_protocol::socket raw(io);
  raw.connect(asio::local::stream_protocol::endpoint(gateway.socket_path));
  asio::write(raw, asio::buffer(std::string("version 2 test\ntransact nonsense\n")));
  asio::streambuf answer;
  asio::read_until(raw, answer, '\n');
  std::istream lines(&answer);
  std::string line;
  std::getline(lines, line);  // the gateway's version
  CHECK(line.rfind("version 2 ", 0) == 0);
  asio::read_until(raw, answer, '\n');
  std::getline(lines, line);
  CHECK(line.rfind("error malformed message", 0) == 0);
  // Everyone else is still served.
  auto fine = RemoteLine::connect(io.get_executor(), gateway.socket_path, "/dev/ttyFAKE0");
  CHECK(fine);
}

TEST_CASE("control socket: a setting reported with no transaction behind it is refused and recorded as refused") {
  AuditTrail trail("");  // before the gateway: it outlives the bus that records into it
  SocketGateway gateway;
  gateway.scheduler.set_audit(trail);
  asio::io_context io;
  auto remote = RemoteLine::connect(io.get_executor(), gateway.socket_path, "/dev/ttyFAKE0");
  REQUIRE(remote);
  const control::SettingChanged filter_2{223, WriteTarget::filter.id, 2, std::nullopt, false};
  const auto forged = (*remote)->setting_changed(filter_2);
  REQUIRE_FALSE(forged.has_value());
  CHECK(forged.error().find("no transaction of this session") != std::string::npos);
  auto records = trail.recent({});
  REQUIRE(records.size() == 1);
  CHECK(records[0].result.starts_with("refused: a setting reported with no transaction"));

  SUBCASE("one reported right after a transaction the line carried is taken, once") {
    FixedLengthReply framer(3);
    REQUIRE(transact(**remote, io, LineRequest{{0x00, 0xDF, 0x01}, 0, &framer}));
    CHECK((*remote)->setting_changed(filter_2).has_value());
    CHECK(trail.recent({}).front().result == "ack");
    // The same transaction does not stand behind a second report.
    CHECK_FALSE((*remote)->setting_changed(filter_2).has_value());
  }
  SUBCASE("one reported answered after a transaction that timed out is refused") {
    std::promise<void> silenced;  // on the gateway's thread, where the line is used
    asio::post(gateway.io, [&] {
      gateway.line.silent = [](const LineRequest&) { return true; };
      silenced.set_value();
    });
    silenced.get_future().wait();
    FixedLengthReply framer(3);
    (void)transact(**remote, io, LineRequest{{0x00, 0xDF, 0x01}, 0, &framer, 20ms, 0});
    const auto claimed = (*remote)->setting_changed(filter_2);
    CHECK_FALSE(claimed.has_value());
    CHECK(trail.recent({}).front().result.starts_with("refused: a setting reported answered"));
  }
}

