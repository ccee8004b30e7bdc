// `--log-level trace` over a real SerialLine on a pseudo-terminal: each request and each reply
// is logged once, in hex, with its direction, its delay and its checksum verdict; a corrupted
// reply, a late one and a 9-bit address are shown for what they are; at debug nothing is.
#include <doctest/doctest.h>

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/this_coro.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "driver/hex.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/reply_framer.h"
#include "modbus_rtu/simulator/simulator.h"
#include "serial/serial_line.h"
#include "sim/support/captured_log.h"
#include "sim/support/rtu_line.h"
#include "sim/support/run_coroutine.h"
#include "sim/support/serial_line_bench.h"
#include "spectron/reply_framers.h"
#include "unit/modbus_rtu/modbus_rtu_test_vectors.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using namespace tiltgate;
using tiltgate::test::CapturedLog;
using tiltgate::test::run_coroutine;

namespace {

using RtuBus = tiltgate::test::RtuLine;

}  // namespace

TEST_CASE("at trace, a request and its reply are logged once each in hex with \"CRC ok\"") {
  RtuBus bus;
  CapturedLog log(spdlog::level::trace);
  REQUIRE(bus.read_filter().has_value());

  const std::string reply = hex_bytes(modbus_rtu::test::framed("01 03 02 00 04"));
  CHECK(log.starting_with("trace rtu1 -> ") ==
        std::vector<std::string>{"trace rtu1 -> 01 03 00 00 00 01 84 0A"});
  const auto received = log.starting_with("trace rtu1 <- ");
  REQUIRE(received.size() == 1);
  CHECK(received[0].rfind("trace rtu1 <- " + reply + " (", 0) == 0);
  CHECK(received[0].find(" ms, CRC ok)") != std::string::npos);
  // The simulator's side (`tiltgate sim`, `demo`): the reply it wrote.
  const std::string simulator = "trace sim " + bus.sim->slave_path();
  CHECK(log.starting_with(simulator + " -> ") ==
        std::vector<std::string>{simulator + " -> " + reply});
}

TEST_CASE("at trace, a reply with a corrupted CRC is logged with its bytes as \"bad CRC\"") {
  RtuBus bus;
  bus.sim->device(1)->faults().corrupt_crc = 1;
  CapturedLog log(spdlog::level::trace);
  CHECK(bus.read_filter().error() == LineError::timeout);

  std::vector<std::uint8_t> corrupted = modbus_rtu::test::framed("01 03 02 00 04");
  corrupted[corrupted.size() - 2] ^= 0xFF;  // the simulator's fault flips the CRC's low byte
  CHECK(log.starting_with("trace rtu1 <- ") ==
        std::vector<std::string>{"trace rtu1 <- " + hex_bytes(corrupted) +
                                 " (no reply within 500 ms: bad CRC)"});

  // The next exchange is clean again.
  REQUIRE(bus.read_filter().has_value());
  const auto received = log.starting_with("trace rtu1 <- ");
  REQUIRE(received.size() == 2);
  CHECK(received.back().find("CRC ok") != std::string::npos);
}

TEST_CASE("at debug, no frame is logged") {
  RtuBus bus;
  CapturedLog log(spdlog::level::debug);
  REQUIRE(bus.read_filter().has_value());
  bus.sim->device(1)->faults().corrupt_crc = 1;
  CHECK_FALSE(bus.read_filter().has_value());
  CHECK(log.starting_with("trace").empty());
  for (const std::string& line : log.lines()) {
    CHECK(line.find("->") == std::string::npos);
    CHECK(line.find("<-") == std::string::npos);
  }
  CHECK_FALSE(log.starting_with("debug rtu1: no reply").empty());  // the capture works
}

TEST_CASE("at trace, a 9-bit request shows its address byte in brackets") {
  using namespace tiltgate::test::line_bench;
  Bench bench([](SerialLineOptions& o) {
    o.framing = Framing::nine_bit;
    o.baud = 28800;
  });
  CapturedLog log(spdlog::level::trace);
  spectron::NineBitReplyFramer framer;
  LineRequest request = request_of(octets(0x05, 'A', '\r', '\n'), &framer);
  request.address_bytes = 1;
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(4);
    co_await bench.far.send(bytes_of("1001\r\n"));
  };
  REQUIRE(bench.exchange(std::move(request), device()).has_value());
  CHECK(log.starting_with("trace line1 -> ") ==
        std::vector<std::string>{"trace line1 -> [05] 41 0D 0A"});
  const auto received = log.starting_with("trace line1 <- ");
  REQUIRE(received.size() == 1);
  CHECK(received[0].rfind("trace line1 <- 31 30 30 31 0D 0A (", 0) == 0);
  CHECK(received[0].find(" ms, CR LF, no checksum)") != std::string::npos);
}

TEST_CASE("at trace, a reply after the time-out is logged as discarded") {
  using namespace tiltgate::test::line_bench;
  Bench bench([](SerialLineOptions& o) {
    o.timeout = 30ms;
    o.late_guard = 150ms;
  });
  CapturedLog log(spdlog::level::trace);
  CountFramer framer(4);
  auto device = [&]() -> asio::awaitable<void> {
    co_await bench.far.receive(2);
    co_await pause(80ms);  // 50 ms past the time-out
    co_await bench.far.send(octets(0xEE, 0xEE, 0xEE, 0xEE));
  };
  CHECK(bench.exchange(request_of(octets(1, 1), &framer), device()).error() == LineError::timeout);
  const auto received = log.starting_with("trace line1 ");
  REQUIRE(received.size() == 3);
  CHECK(received[0] == "trace line1 -> 01 01");
  CHECK(received[1] == "trace line1 no reply within 30 ms");
  CHECK(received[2].rfind("trace line1 <- EE EE EE EE (discarded: late, ", 0) == 0);
}
