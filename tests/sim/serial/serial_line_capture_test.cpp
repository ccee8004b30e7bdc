// What a real SerialLine on a pseudo-terminal gives its frame recorder (capture/black_box.h):
// each request and each reply once, in wire order, with the time of its first byte, its
// direction and the line's verdict; a corrupted reply, a late one and a 9-bit address as what
// they are.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <chrono>
#include <optional>
#include <vector>

#include "capture/black_box.h"
#include "serial/serial_line.h"
#include "sim/support/rtu_line.h"
#include "sim/support/run_coroutine.h"
#include "sim/support/serial_line_bench.h"
#include "spectron/reply_framers.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using namespace tiltgate;

namespace {

// The bus's line records into a black box of a minute.
struct CaptureRtuBus : tiltgate::test::RtuLine {
  BlackBox box{std::chrono::seconds(60)};
  CaptureRtuBus() : RtuLine(std::chrono::milliseconds(300)) { line->record_frames_to(&box); }
};

}  // namespace

TEST_CASE("a line records its request and the reply, in order, with their verdicts") {
  CaptureRtuBus bus;
  const auto before = std::chrono::system_clock::now();
  REQUIRE(bus.read_filter().has_value());
  const auto after = std::chrono::system_clock::now();
  const std::vector<CapturedFrame> frames = bus.box.held();
  REQUIRE(frames.size() == 2);
  CHECK(frames[0].direction == FrameDirection::to_devices);
  CHECK(frames[0].bytes == std::vector<std::uint8_t>{0x01, 0x03, 0x00, 0x00, 0x00, 0x01, 0x84, 0x0A});
  CHECK(frames[0].verdict == "request");
  CHECK(frames[1].direction == FrameDirection::from_devices);
  CHECK(frames[1].bytes == modbus_rtu::test::framed("01 03 02 00 04"));
  CHECK(frames[1].verdict == "CRC ok");
  CHECK(before <= frames[0].time);
  CHECK(frames[0].time <= frames[1].time);
  CHECK(frames[1].time <= after);
  CHECK(bus.line->frames_kept() == std::chrono::seconds(60));
}

TEST_CASE("a reply with a corrupted CRC is recorded with its bytes as no reply, bad CRC") {
  CaptureRtuBus bus;
  bus.sim->device(1)->faults().corrupt_crc = 1;
  CHECK(bus.read_filter().error() == LineError::timeout);
  std::vector<std::uint8_t> corrupted = modbus_rtu::test::framed("01 03 02 00 04");
  corrupted[corrupted.size() - 2] ^= 0xFF;  // the simulator's fault flips the CRC's low byte
  const std::vector<CapturedFrame> frames = bus.box.held();
  REQUIRE(frames.size() == 2);
  CHECK(frames[1].bytes == corrupted);
  CHECK(frames[1].verdict == "no reply: bad CRC");
}

TEST_CASE("a line without a recorder records nothing and says it keeps nothing") {
  CaptureRtuBus bus;
  bus.line->record_frames_to(nullptr);
  REQUIRE(bus.read_filter().has_value());
  CHECK(bus.box.held().empty());
  CHECK(bus.line->frames_kept() == std::chrono::seconds(0));
}

TEST_CASE("a 9-bit request is recorded with its address byte counted") {
  using namespace tiltgate::test::line_bench;
  Bench bench([](SerialLineOptions& o) {
    o.framing = Framing::nine_bit;
    o.baud = 28800;
  });
  BlackBox box(std::chrono::seconds(10));
  bench.line->record_frames_to(&box);
  spectron::NineBitReplyFramer framer;
  LineRequest request = request_of(octets(0x05, 'A', '\r', '\n'), &framer);
  request.address_bytes = 1;
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(4);
    co_await bench.far.send(bytes_of("1001\r\n"));
  };
  REQUIRE(bench.exchange(std::move(request), device()).has_value());
  const std::vector<CapturedFrame> frames = box.held();
  REQUIRE(frames.size() == 2);
  CHECK(frames[0].address_bytes == 1);
  CHECK(frames[0].bytes == octets(0x05, 'A', '\r', '\n'));
  CHECK(frames[1].address_bytes == 0);
  CHECK(frames[1].bytes == bytes_of("1001\r\n"));
}

TEST_CASE("a reply after the time-out is recorded as late, apart from the silent attempt") {
  using namespace tiltgate::test::line_bench;
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 30ms;
    o.late_guard = 150ms;
  });
  BlackBox box(std::chrono::seconds(10));
  bench.line->record_frames_to(&box);
  CountFramer framer(4);
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(2);
    co_await pause(80ms);  // 50 ms past the time-out
    co_await bench.far.send(octets(0xEE, 0xEE, 0xEE, 0xEE));
  };
  CHECK(bench.exchange(request_of(octets(1, 1), &framer), device()).error() == LineError::timeout);
  const std::vector<CapturedFrame> frames = box.held();
  REQUIRE(frames.size() == 2);
  CHECK(frames[0].verdict == "request");
  CHECK(frames[1].bytes == octets(0xEE, 0xEE, 0xEE, 0xEE));
  CHECK(frames[1].verdict == "late: after its request's time-out");
  CHECK(frames[1].time - frames[0].time >= 60ms);
}
