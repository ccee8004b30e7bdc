// SerialLine's port settings over a pseudo-terminal: baud rates, 9-bit and 8E1 parity, kernel
// RS485 mode, and the mapping from the bus configuration.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "gateway/serial_options.h"
#include "sim/support/serial_line_bench.h"

namespace asio = boost::asio;
using namespace std::chrono_literals;
using namespace tiltgate::test::line_bench;
using tiltgate::LineRequest;
using tiltgate::Parity;
using tiltgate::SerialLineOptions;

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

TEST_CASE("the bus configuration maps onto line options and framing") {
  tiltgate::BusConfig bus;
  bus.name = "east";
  bus.port = "/dev/ttyUSB3";
  bus.protocol = "spectron-9bit";
  bus.baud = 28800;
  bus.timeout = 80ms;
  bus.retries = 4;
  bus.gap = 1500us;
  bus.echo = true;
  const SerialLineOptions o = tiltgate::serial_options_from(tiltgate::registered_families(), bus);
  CHECK(o.name == "east");
  CHECK(o.port == "/dev/ttyUSB3");
  CHECK(o.baud == 28800);
  CHECK(o.timeout == 80ms);
  CHECK(o.retries == 4);
  CHECK(o.gap == 1500us);
  CHECK(o.echo);
  CHECK(o.framing == tiltgate::Framing::nine_bit);
  bus.protocol = "spectron-modbus";
  CHECK(tiltgate::serial_options_from(tiltgate::registered_families(), bus).framing == tiltgate::Framing::eight_even_one);
  bus.protocol = "rieker";
  CHECK(tiltgate::serial_options_from(tiltgate::registered_families(), bus).framing == tiltgate::Framing::eight_none_one);
}

TEST_CASE("Modbus RTU framings set their parity and stop bits on the port") {
  // A pty clears PARENB (see termios_settings_test.cpp), so the parity shows as PARODD only.
  struct Case {
    tiltgate::Framing framing;
    bool odd;
    int stop_bits;
    Parity written;
  };
  const Bytes request = {0x01, 0x03};
  for (Case e : {Case{tiltgate::Framing::eight_even_one, false, 1, Parity::even},
                 Case{tiltgate::Framing::eight_odd_one, true, 1, Parity::odd},
                 Case{tiltgate::Framing::eight_none_two, false, 2, Parity::none},
                 Case{tiltgate::Framing::eight_none_one, false, 1, Parity::none}}) {
    CAPTURE(int(e.framing));
    Bench bench([&](SerialLineOptions& o) {
      o.baud = 19200;
      o.framing = e.framing;
    });
    const auto in_force = bench.line->termios_in_force();
    REQUIRE(in_force.has_value());
    CHECK(in_force->data_bits == 8);
    CHECK(in_force->stop_bits == e.stop_bits);
    CHECK(in_force->odd_parity == e.odd);
    CHECK_FALSE(in_force->stick_parity);
    std::vector<Parity> applied;
    bench.line->observe_writes([&](std::span<const std::uint8_t>, Parity parity,
                                   const tiltgate::TtySettings&) { applied.push_back(parity); });
    auto device = [&]() -> asio::awaitable<void> {
      CHECK(co_await bench.far.receive(2) == request);
    };
    CHECK(bench.exchange(request_of(request, nullptr), device()).has_value());
    CHECK(run_until(bench.io, [&] { return bench.far.arrivals.size() == 1; }));
    CHECK(applied == std::vector<Parity>{e.written});
  }
}

TEST_CASE("a bus's own framing overrides its protocol's") {
  tiltgate::BusConfig bus;
  bus.protocol = "spectron-modbus";
  bus.framing = tiltgate::Framing::eight_none_two;
  CHECK(tiltgate::serial_options_from(tiltgate::registered_families(), bus).framing == tiltgate::Framing::eight_none_two);
}
