// SerialLine against a scripted far end on the master side of a pseudo-terminal, both on one
// io_context. Timing assertions are lower bounds only.
#include "serial/serial_line.h"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "serial/pseudo_terminal.h"

namespace asio = boost::asio;
namespace fs = std::filesystem;
using namespace std::chrono_literals;
using Bytes = std::vector<std::uint8_t>;
using Clock = std::chrono::steady_clock;
using Result = tiltgate::Expected<tiltgate::Done, tiltgate::LineError>;
using tiltgate::LineError;
using tiltgate::LineRequest;
using tiltgate::Parity;
using tiltgate::PseudoTerminal;
using tiltgate::SerialLine;
using tiltgate::SerialLineOptions;

namespace {

// Complete once `size` bytes have arrived; later bytes are ignored.
class CountFramer : public tiltgate::ReplyFramer {
 public:
  explicit CountFramer(std::size_t size) : size_(size) {}
  void reset() override { bytes.clear(); }
  bool feed(std::span<const std::uint8_t> chunk) override {
    ++feeds;
    for (std::uint8_t b : chunk) {
      if (bytes.size() < size_) bytes.push_back(b);
    }
    return bytes.size() == size_;
  }
  Bytes bytes;
  int feeds = 0;

 private:
  std::size_t size_;
};

// Complete at the first '\n'.
class LineEndFramer : public tiltgate::ReplyFramer {
 public:
  void reset() override { text.clear(); }
  bool feed(std::span<const std::uint8_t> chunk) override {
    for (std::uint8_t b : chunk) {
      text.push_back(char(b));
      if (b == '\n') return true;
    }
    return false;
  }
  std::string text;
};

Bytes bytes_of(const std::string& text) { return Bytes(text.begin(), text.end()); }

// Braced lists cannot appear in an expression with co_await (g++ 12 rejects the
// initializer_list's backing array in a coroutine frame), so coroutines build bytes with this.
template <class... Byte>
Bytes octets(Byte... b) {
  return Bytes{std::uint8_t(b)...};
}

PseudoTerminal open_pty() {
  auto pty = PseudoTerminal::open();
  REQUIRE_MESSAGE(pty.has_value(), (pty ? "" : pty.error()));
  return std::move(*pty);
}

// The device side: the master end of the pty.
class FarEnd {
 public:
  FarEnd(asio::io_context& io, PseudoTerminal& pty) : port_(io, pty.release_master()) {}

  // Exactly `size` bytes; notes when they were read.
  asio::awaitable<Bytes> receive(std::size_t size) {
    Bytes bytes(size);
    co_await asio::async_read(port_, asio::buffer(bytes), asio::use_awaitable);
    arrivals.push_back(Clock::now());
    co_return bytes;
  }
  asio::awaitable<void> send(Bytes bytes) {
    co_await asio::async_write(port_, asio::buffer(bytes), asio::use_awaitable);
  }
  // A device that never answers: reads and counts everything.
  asio::awaitable<void> listen_silently() {
    std::array<std::uint8_t, 64> buffer{};
    for (boost::system::error_code ec; !ec;) {
      received += co_await port_.async_read_some(asio::buffer(buffer),
                                                 asio::redirect_error(asio::use_awaitable, ec));
    }
  }
  // The adapter is unplugged: the slave side hangs up.
  void close() { port_.close(); }
  int native() { return port_.native_handle(); }

  std::vector<Clock::time_point> arrivals;
  std::size_t received = 0;

 private:
  asio::posix::stream_descriptor port_;
};

SerialLineOptions options_for(const std::string& port) {
  SerialLineOptions o;
  o.name = "line1";
  o.port = port;
  o.baud = 125000;
  o.timeout = 2000ms;  // generous: only the silent-device tests wait it out, with their own
  o.retries = 0;
  o.gap = 1000us;
  o.reopen_min = 10ms;
  o.reopen_max = 40ms;
  return o;
}

// Runs the io_context until `done` holds; false if it does not within `limit`.
bool run_until(asio::io_context& io, const std::function<bool()>& done,
               Clock::duration limit = 5s) {
  const auto deadline = Clock::now() + limit;
  io.restart();  // an io_context that ran out of work earlier stays stopped until restarted
  while (!done() && Clock::now() < deadline) io.run_one_for(deadline - Clock::now());
  return done();
}

// Polls `condition` every millisecond for up to `limit`, inside a coroutine.
asio::awaitable<bool> eventually(std::function<bool()> condition, Clock::duration limit = 3s) {
  asio::steady_timer timer(co_await asio::this_coro::executor);
  const auto deadline = Clock::now() + limit;
  while (!condition()) {
    if (Clock::now() >= deadline) co_return false;
    timer.expires_after(1ms);
    co_await timer.async_wait(asio::use_awaitable);
  }
  co_return true;
}

// One transaction run to its end (the test fails if it does not end within 5 s).
Result transact(asio::io_context& io, SerialLine& line, LineRequest request) {
  std::optional<Result> result;
  auto body = [&]() -> asio::awaitable<void> {
    result = co_await line.transact(std::move(request));
  };
  asio::co_spawn(io, body(), asio::detached);
  REQUIRE_MESSAGE(run_until(io, [&] { return result.has_value(); }), "transact did not end");
  return *result;
}

LineRequest request_of(Bytes bytes, tiltgate::ReplyFramer* framer) {
  LineRequest r;
  r.bytes = std::move(bytes);
  r.framer = framer;
  return r;
}

// A pty whose far end the test scripts, and a started line on its slave side.
struct Bench {
  explicit Bench(const std::function<void(SerialLineOptions&)>& adjust = {}) {
    SerialLineOptions options = options_for(pty.slave_path());
    if (adjust) adjust(options);
    line = std::make_unique<SerialLine>(io.get_executor(), options);
    REQUIRE(line->start());
  }
  Result transact(LineRequest request) { return ::transact(io, *line, std::move(request)); }
  // Starts the device's script, then runs the transaction.
  Result exchange(LineRequest request, asio::awaitable<void> device) {
    asio::co_spawn(io, std::move(device), asio::detached);
    return transact(std::move(request));
  }

  asio::io_context io;
  PseudoTerminal pty = open_pty();
  FarEnd far{io, pty};
  std::unique_ptr<SerialLine> line;
};

// Symlinks in a fresh directory stand for a device path that can vanish and come back.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (fs::temp_directory_path() / "serial_line_test.XXXXXX").string();
    REQUIRE(::mkdtemp(pattern.data()) != nullptr);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  fs::path operator/(const char* name) const { return path_ / name; }
  // Atomically points `link` at `target` (rename over the old link).
  void point(const fs::path& link, const fs::path& target) const {
    const fs::path fresh = path_ / "new-link";
    fs::create_symlink(target, fresh);
    fs::rename(fresh, link);
  }

 private:
  fs::path path_;
};

}  // namespace

TEST_CASE("a transaction before start finds the line closed") {
  asio::io_context io;
  SerialLine line(io.get_executor(), options_for("/nonexistent/tty"));
  CHECK(transact(io, line, request_of({1}, nullptr)).error() == LineError::closed);
  CHECK(line.generation() == 0);
}

TEST_CASE("a reply split into many chunks is assembled by the framer") {
  Bench bench;
  CountFramer framer(6);
  const Bytes reply{10, 11, 12, 13, 14, 15};
  auto device = [&]() -> asio::awaitable<void> {
    CHECK(co_await bench.far.receive(3) == octets(1, 2, 3));
    for (std::size_t i = 0; i < reply.size(); ++i) {
      co_await bench.far.send(octets(reply[i]));
      // The next byte only once the line has fed this one, so each is a chunk of its own.
      co_await eventually([&] { return framer.bytes.size() == i + 1; });
    }
  };
  CHECK(bench.exchange(request_of({1, 2, 3}, &framer), device()).has_value());
  CHECK(framer.bytes == reply);
  CHECK(framer.feeds == 6);
  CHECK(bench.line->stats().attempts == 1);
  CHECK(bench.line->stats().timeouts == 0);
}

TEST_CASE("a silent device times out after every retry, each attempt counted") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 20ms;
    o.retries = 2;
  });
  CountFramer framer(1);
  asio::co_spawn(bench.io, bench.far.listen_silently(), asio::detached);
  CHECK(bench.transact(request_of({1, 2, 3}, &framer)).error() == LineError::timeout);
  LineRequest once = request_of({4, 5, 6}, &framer);
  once.retries = 0;  // e.g. Set Address, which must not run twice
  CHECK(bench.transact(std::move(once)).error() == LineError::timeout);
  CHECK(run_until(bench.io, [&] { return bench.far.received == 12; }));
  CHECK(bench.line->stats().attempts == 4);
  CHECK(bench.line->stats().timeouts == 4);
  CHECK(bench.line->stats().io_errors == 0);
  CHECK(bench.line->is_open());
}

TEST_CASE("a retry starts the reply afresh") {
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 300ms;  // the whole reply must make it within one attempt, even on a busy machine
    o.retries = 1;
  });
  CountFramer framer(4);
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(2);
    co_await bench.far.send(octets(0xAA, 0xBB));  // half a reply, then silence
    co_await bench.far.receive(2);
    co_await bench.far.send(octets(1, 2, 3, 4));
  };
  CHECK(bench.exchange(request_of({7, 8}, &framer), device()).has_value());
  CHECK(framer.bytes == Bytes{1, 2, 3, 4});
  CHECK(bench.line->stats().attempts == 2);
  CHECK(bench.line->stats().timeouts == 1);
}

TEST_CASE("the quiet gap and a request's settle time separate master packets") {
  // Each packet's departure is noted by the write hook, right as its write completes; the
  // next packet's arrival is noted by the far end. The line also waits out the 12.5 ms a
  // 12-byte packet takes at 9600 baud, which covers the hook's few microseconds of lateness.
  // (Arrival-to-arrival would not do: the far end may read the first packet late.)
  Bench bench([](SerialLineOptions& o) {
    o.baud = 9600;
    o.gap = 20ms;
  });
  std::vector<Clock::time_point> departures;
  bench.line->observe_writes([&](std::span<const std::uint8_t>, Parity,
                                 const tiltgate::TtySettings&) {
    departures.push_back(Clock::now());
  });
  const Bytes packet(12, 0x42);
  auto device = [&]() -> asio::awaitable<void> {
    for (int i = 0; i < 3; ++i) co_await bench.far.receive(packet.size());
  };
  CHECK(bench.exchange(request_of(packet, nullptr), device()).has_value());
  LineRequest settling = request_of(packet, nullptr);
  settling.settle = 50ms;  // Rieker: 50 ms after Set Address
  CHECK(bench.transact(std::move(settling)).has_value());
  CHECK(bench.transact(request_of(packet, nullptr)).has_value());
  REQUIRE(run_until(bench.io, [&] { return bench.far.arrivals.size() == 3; }));
  REQUIRE(departures.size() == 3);
  CHECK(bench.far.arrivals[1] - departures[0] >= 20ms);
  CHECK(bench.far.arrivals[2] - departures[1] >= 70ms);
  CHECK(bench.line->stats().attempts == 3);
}

TEST_CASE("the adapter's echo of the request is skipped before the reply") {
  Bench bench([](SerialLineOptions& o) { o.echo = true; });
  const Bytes request{0x01, 0x02, 0x03, 0x04};
  LineEndFramer framer;
  auto device = [&]() -> asio::awaitable<void> {
    // Echo and reply in one chunk, then echo and reply apart.
    Bytes echo_and_reply = co_await bench.far.receive(request.size());
    for (std::uint8_t b : bytes_of("first\n")) echo_and_reply.push_back(b);
    co_await bench.far.send(echo_and_reply);
    co_await bench.far.send(co_await bench.far.receive(request.size()));
    co_await bench.far.send(bytes_of("second\n"));
  };
  CHECK(bench.exchange(request_of(request, &framer), device()).has_value());
  CHECK(framer.text == "first\n");
  CHECK(bench.transact(request_of(request, &framer)).has_value());
  CHECK(framer.text == "second\n");
  CHECK(bench.line->echo_mismatches() == 0);
}

TEST_CASE("an echo that differs from the request fails the attempt as a collision") {
  Bench bench([](SerialLineOptions& o) {
    o.echo = true;
    o.retries = 1;
  });
  LineEndFramer framer;
  auto device = [&]() -> asio::awaitable<void> {
    for (int attempt = 0; attempt < 2; ++attempt) {
      Bytes garbled = co_await bench.far.receive(3);
      garbled[1] ^= 0xFF;
      garbled.push_back('\n');
      co_await bench.far.send(garbled);
    }
  };
  CHECK(bench.exchange(request_of(bytes_of("abc"), &framer), device()).error() ==
        LineError::timeout);
  CHECK(bench.line->echo_mismatches() == 2);
  CHECK(bench.line->stats().attempts == 2);
  CHECK(bench.line->stats().io_errors == 0);
}

TEST_CASE("input received before a request is discarded") {
  Bench bench;
  LineEndFramer framer;
  // Wait, through a second descriptor on the slave, until the stale bytes have reached it.
  const int watcher = ::open(bench.pty.slave_path().c_str(), O_RDONLY | O_NOCTTY | O_NONBLOCK);
  REQUIRE(watcher >= 0);
  const std::string junk = "late reply\n";
  REQUIRE(::write(bench.far.native(), junk.data(), junk.size()) == ssize_t(junk.size()));
  pollfd p{watcher, POLLIN, 0};
  REQUIRE(::poll(&p, 1, 2000) == 1);
  ::close(watcher);
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(1);
    co_await bench.far.send(bytes_of("fresh\n"));
  };
  CHECK(bench.exchange(request_of(bytes_of("?"), &framer), device()).has_value());
  CHECK(framer.text == "fresh\n");
}

TEST_CASE("an unplugged port gives io then closed, and reopens when it is back") {
  TempDir dir;
  const fs::path port = dir / "ttyUSB0";
  asio::io_context io;
  PseudoTerminal first = open_pty();
  FarEnd first_end(io, first);
  dir.point(port, first.slave_path());
  SerialLine line(io.get_executor(), options_for(port.string()));
  REQUIRE(line.start());
  CHECK(line.generation() == 1);

  // Unplugged: the device path goes away and the tty hangs up.
  dir.point(port, dir / "absent");
  first_end.close();
  first.close();
  CountFramer framer(1);
  CHECK(transact(io, line, request_of({1}, &framer)).error() == LineError::io);
  CHECK_FALSE(line.is_open());
  CHECK(transact(io, line, request_of({1}, &framer)).error() == LineError::closed);
  io.restart();
  io.run_for(50ms);  // several reopen attempts fail meanwhile
  CHECK(transact(io, line, request_of({1}, &framer)).error() == LineError::closed);

  // Plugged in again, as a different tty behind the same path.
  PseudoTerminal second = open_pty();
  FarEnd second_end(io, second);
  dir.point(port, second.slave_path());
  REQUIRE(run_until(io, [&] { return line.is_open(); }));
  CHECK(line.generation() == 2);
  CHECK(line.stats().reopens == 1);
  CHECK(line.stats().io_errors == 1);
  auto device = [&]() -> asio::awaitable<void> {
    co_await second_end.receive(1);
    co_await second_end.send(octets(0x99));
  };
  asio::co_spawn(io, device(), asio::detached);
  CHECK(transact(io, line, request_of({2}, &framer)).has_value());
  CHECK(framer.bytes == Bytes{0x99});
}

TEST_CASE("a port missing at start is opened once it appears") {
  TempDir dir;
  const fs::path port = dir / "ttyUSB0";
  asio::io_context io;
  PseudoTerminal pty = open_pty();
  SerialLine line(io.get_executor(), options_for(port.string()));
  CHECK_FALSE(line.start());
  CHECK(transact(io, line, request_of({1}, nullptr)).error() == LineError::closed);
  dir.point(port, pty.slave_path());
  CHECK(run_until(io, [&] { return line.is_open(); }));
  CHECK(line.generation() == 1);
  CHECK(line.stats().reopens == 0);
}

TEST_CASE("the line sets non-standard baud rates, read back from the port") {
  for (std::uint32_t baud : {9600u, 62500u, 125000u, 128000u, 250000u}) {
    CAPTURE(baud);
    Bench bench([baud](SerialLineOptions& o) { o.baud = baud; });
    const auto in_force = bench.line->termios_in_force();
    REQUIRE(in_force.has_value());
    CHECK(in_force->output_baud == baud);
    CHECK(in_force->input_baud == baud);
    CHECK(in_force->raw);
    CHECK(in_force->receiver_on);
    CHECK_FALSE(in_force->flow_control);
  }
}

TEST_CASE("9-bit framing sends the address with mark parity and the data with space parity") {
  Bench bench([](SerialLineOptions& o) {
    o.framing = tiltgate::Framing::nine_bit;
    o.baud = 28800;
  });
  struct Write {
    Bytes bytes;
    Parity applied;
    tiltgate::TtySettings in_force;
  };
  std::vector<Write> writes;
  bench.line->observe_writes([&](std::span<const std::uint8_t> bytes, Parity applied,
                                 const tiltgate::TtySettings& in_force) {
    writes.push_back({Bytes(bytes.begin(), bytes.end()), applied, in_force});
  });
  LineEndFramer framer;
  const Bytes request{0x05, 'A', '\r', '\n'};
  auto device = [&]() -> asio::awaitable<void> {
    CHECK(co_await bench.far.receive(request.size()) == request);
    co_await bench.far.send(bytes_of("1001\r\n"));
  };
  LineRequest addressed = request_of(request, &framer);
  addressed.address_bytes = 1;
  CHECK(bench.exchange(std::move(addressed), device()).has_value());
  CHECK(framer.text == "1001\r\n");
  REQUIRE(writes.size() == 2);
  CHECK(writes[0].bytes == Bytes{0x05});
  CHECK(writes[0].applied == Parity::mark);
  // A pty clears PARENB; the stick (CMSPAR) and odd (PARODD) bits show mark vs space.
  CHECK(writes[0].in_force.stick_parity);
  CHECK(writes[0].in_force.odd_parity);
  CHECK(writes[1].bytes == bytes_of("A\r\n"));
  CHECK(writes[1].applied == Parity::space);
  CHECK(writes[1].in_force.stick_parity);
  CHECK_FALSE(writes[1].in_force.odd_parity);
  const auto after = bench.line->termios_in_force();
  REQUIRE(after.has_value());
  CHECK(after->ignores_parity_errors);
  CHECK_FALSE(after->checks_input_parity);
  CHECK(after->output_baud == 28800);
}

TEST_CASE("8E1 framing writes the whole packet with even parity") {
  Bench bench([](SerialLineOptions& o) { o.framing = tiltgate::Framing::eight_even_one; });
  std::vector<Parity> applied;
  bench.line->observe_writes([&](std::span<const std::uint8_t>, Parity parity,
                                 const tiltgate::TtySettings&) { applied.push_back(parity); });
  LineRequest r = request_of(bytes_of(":016633\r\n"), nullptr);
  r.address_bytes = 1;  // ignored: only a 9-bit bus has address bytes
  auto device = [&]() -> asio::awaitable<void> {
    CHECK(co_await bench.far.receive(9) == bytes_of(":016633\r\n"));
  };
  CHECK(bench.exchange(std::move(r), device()).has_value());
  CHECK(run_until(bench.io, [&] { return bench.far.arrivals.size() == 1; }));
  CHECK(applied == std::vector<Parity>{Parity::even});
}

TEST_CASE("kernel RS485 mode, refused by a pty, leaves the line working") {
  Bench bench([](SerialLineOptions& o) { o.rs485_kernel = true; });
  CHECK(bench.line->is_open());
  auto device = [&]() -> asio::awaitable<void> {
    CHECK(co_await bench.far.receive(2) == octets(0x10, 0x20));
  };
  CHECK(bench.exchange(request_of({0x10, 0x20}, nullptr), device()).has_value());
  CHECK(run_until(bench.io, [&] { return bench.far.arrivals.size() == 1; }));
}

TEST_CASE("stop cancels a pending transaction and every later one") {
  Bench bench([](SerialLineOptions& o) { o.timeout = 10000ms; });
  CountFramer framer(1);
  auto stopper = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(1);  // the request is out: the line now waits for a reply
    bench.line->stop();
  };
  CHECK(bench.exchange(request_of({1}, &framer), stopper()).error() == LineError::cancelled);
  CHECK(bench.transact(request_of({1}, &framer)).error() == LineError::cancelled);
  CHECK_FALSE(bench.line->is_open());
  CHECK(bench.line->stats().timeouts == 0);
}

TEST_CASE("the bus configuration maps onto line options and framing") {
  tiltgate::BusConfig bus;
  bus.name = "east";
  bus.port = "/dev/ttyUSB3";
  bus.protocol = tiltgate::BusProtocol::spectron_9bit;
  bus.baud = 28800;
  bus.timeout = 80ms;
  bus.retries = 4;
  bus.gap = 1500us;
  bus.echo = true;
  const SerialLineOptions o = tiltgate::from_config(bus);
  CHECK(o.name == "east");
  CHECK(o.port == "/dev/ttyUSB3");
  CHECK(o.baud == 28800);
  CHECK(o.timeout == 80ms);
  CHECK(o.retries == 4);
  CHECK(o.gap == 1500us);
  CHECK(o.echo);
  CHECK(o.framing == tiltgate::Framing::nine_bit);
  bus.protocol = tiltgate::BusProtocol::spectron_modbus;
  CHECK(tiltgate::from_config(bus).framing == tiltgate::Framing::eight_even_one);
  bus.protocol = tiltgate::BusProtocol::rieker;
  CHECK(tiltgate::from_config(bus).framing == tiltgate::Framing::eight_none_one);
}
