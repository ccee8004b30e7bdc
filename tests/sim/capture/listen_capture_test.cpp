// `tiltgate capture --port` as capture_command.cpp runs it: run_listen_capture on a pseudo-
// terminal that a thread of the test drives like the line's master and sensor, for a set
// duration; and the options it refuses before it opens anything.
#include <doctest/doctest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <iostream>
#include <sstream>
#include <thread>
#include <vector>

#include "capture_cli/listen_capture.h"
#include "driver/family.h"
#include "serial/pseudo_terminal.h"
#include "serial/termios_settings.h"
#include "unit/rieker/rieker_test_vectors.h"

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using Bytes = std::vector<std::uint8_t>;

// What run_listen_capture says on stderr, while it runs.
class StderrCapture {
 public:
  StderrCapture() : previous_(std::cerr.rdbuf(text_.rdbuf())) {}
  ~StderrCapture() { std::cerr.rdbuf(previous_); }
  std::string text() const { return text_.str(); }

 private:
  std::ostringstream text_;
  std::streambuf* previous_;
};

const ProtocolDescriptor& protocol_named(std::string_view name) {
  const ProtocolEntry entry = find_protocol(registered_families(), name);
  REQUIRE(entry.protocol != nullptr);
  return *entry.protocol;
}

ListenCaptureOptions options_for(std::string port, std::string_view protocol, std::uint32_t baud) {
  ListenCaptureOptions options;
  options.port = std::move(port);
  options.protocol = &protocol_named(protocol);
  options.baud = baud;
  options.duration = 1s;
  return options;
}

int capture_nothing(const ListenCaptureOptions& options, std::string& said) {
  StderrCapture stderr_text;
  const int code = run_listen_capture(options, [](const CapturedFrame&) { return true; });
  said = stderr_text.text();
  return code;
}

}  // namespace

TEST_CASE("a listen-only capture hands on every frame heard for its duration, then sums up") {
  auto pty = PseudoTerminal::open();
  REQUIRE_MESSAGE(pty.has_value(), (pty ? "" : pty.error()));
  constexpr std::uint32_t kBaud = 19200;
  constexpr int kExchanges = 5;
  const Bytes request = rieker::test::hex("0065 0000 001E 00 5500");  // Get Lock Level
  const Bytes reply = rieker::test::hex("0000 0065 001E 01 01 5EEC");

  // The line's master and sensor, once the capture has set the port to the bus's rate (a
  // pseudo-terminal's two sides share their settings) and dropped what came before.
  std::atomic<bool> fed{false};
  std::thread line([&] {
    const auto give_up = std::chrono::steady_clock::now() + 5s;
    while (std::chrono::steady_clock::now() < give_up) {
      const auto settings = read_settings(pty->master_fd());
      if (settings && settings->input_baud == kBaud) break;
      std::this_thread::sleep_for(5ms);
    }
    std::this_thread::sleep_for(100ms);
    for (int i = 0; i < kExchanges; ++i) {
      (void)!::write(pty->master_fd(), request.data(), request.size());
      std::this_thread::sleep_for(3ms);
      (void)!::write(pty->master_fd(), reply.data(), reply.size());
      std::this_thread::sleep_for(50ms);
    }
    fed = true;
  });

  std::vector<CapturedFrame> frames;
  int code = -1;
  std::string said;
  {
    StderrCapture stderr_text;
    code = run_listen_capture(options_for(pty->slave_path(), "rieker", kBaud),
                              [&](const CapturedFrame& frame) {
                                frames.push_back(frame);
                                return true;
                              });
    said = stderr_text.text();
  }
  line.join();
  CHECK(fed);
  CHECK(code == 0);
  REQUIRE(frames.size() == 2 * kExchanges);
  for (std::size_t i = 0; i < frames.size(); i += 2) {
    CHECK(frames[i].bytes == request);
    CHECK(frames[i].verdict == "request, CRC ok");
    CHECK(frames[i].direction == FrameDirection::to_devices);
    CHECK(frames[i + 1].bytes == reply);
    CHECK(frames[i + 1].verdict == "reply, CRC ok");
    CHECK(frames[i + 1].time > frames[i].time);
  }
  CHECK(said.find("10 frames, 5 requests, 5 replies paired, 0 no reply, 0 garbled") !=
        std::string::npos);
}

TEST_CASE("a listen-only capture stops when the output refuses a frame") {
  auto pty = PseudoTerminal::open();
  REQUIRE_MESSAGE(pty.has_value(), (pty ? "" : pty.error()));
  const Bytes request = rieker::test::hex("0065 0000 001E 00 5500");
  std::thread line([&] {
    std::this_thread::sleep_for(300ms);
    (void)!::write(pty->master_fd(), request.data(), request.size());
  });
  ListenCaptureOptions options = options_for(pty->slave_path(), "rieker", 19200);
  options.duration = 10s;
  StderrCapture stderr_text;
  const auto started = std::chrono::steady_clock::now();
  // The request alone is handed on once its reply window closes.
  const int code = run_listen_capture(options, [](const CapturedFrame&) { return false; });
  line.join();
  CHECK(code == 1);
  CHECK(std::chrono::steady_clock::now() - started < 5s);
}

TEST_CASE("a listen-only capture refuses a TCP protocol, a fixed framing and a foreign rate") {
  std::string said;
  CHECK(capture_nothing(options_for("/dev/null", "modbus-tcp", 19200), said) == 2);
  CHECK(said.find("no serial line to listen to") != std::string::npos);

  ListenCaptureOptions parity = options_for("/dev/null", "rieker", 19200);
  parity.parity = "even";
  CHECK(capture_nothing(parity, said) == 2);
  CHECK(said.find("fixed framing") != std::string::npos);

  CHECK(capture_nothing(options_for("/dev/null", "rieker", 4800), said) == 2);
  CHECK(said.find("--baud 4800") != std::string::npos);

  ListenCaptureOptions two_stops = options_for("/dev/null", "modbus-rtu", 19200);
  two_stops.parity = "even";
  two_stops.stop_bits = 2;
  CHECK(capture_nothing(two_stops, said) == 2);
}

TEST_CASE("a listen-only capture on a tty it cannot open says so and fails") {
  std::string said;
  CHECK(capture_nothing(options_for("/nonexistent/ttyUSB9", "modbus-rtu", 19200), said) == 1);
  CHECK(said.find("cannot listen on /nonexistent/ttyUSB9") != std::string::npos);
}
