// The gateway's side of pass-through without a socket: RequestRouter forwards requests for
// passed-through unit ids to their bus (only reads while [server] writes is false), and the
// reply ADU carries the request's MBAP header with the relayed PDU. Every passed-through request
// that may change the device is one audit record, from what the bus carried and got back.
#include <doctest/doctest.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <optional>

#include "audit/audit_trail.h"
#include "line_scheduling/bus_scheduler.h"
#include "modbus_tcp/modbus_request.h"
#include "gateway/request_router.h"
#include "unit/support/fake_bus.h"
#include "unit/support/fake_forwarding.h"

using namespace tiltgate;
using namespace tiltgate::test;
using namespace std::chrono_literals;
namespace asio = boost::asio;

namespace {

using Bytes = std::vector<std::uint8_t>;

// A router with unit 30 passed through to a bus whose device echoes every PDU.
struct Plant {
  explicit Plant(bool writes) : router(io.get_executor(), RouterOptions{writes, WordOrder::big, 3000ms}) {
    line.reply = [this](const LineRequest& request) {
      ++sent;
      return request.bytes;
    };
    scheduler.enable_forwarding(echo_forward);
    scheduler.set_audit(trail);
    router.pass_through(30, lent(scheduler));
    asio::co_spawn(io, scheduler.run(), asio::detached);
  }
  ~Plant() {
    scheduler.stop();
    io.restart();
    io.run_for(100ms);
  }

  ForwardedReply forward(std::uint8_t unit, Bytes pdu) {
    std::optional<ForwardedReply> reply;
    asio::co_spawn(
        io,
        [&]() -> asio::awaitable<void> {
          // Named, not a temporary in the co_await: g++ 12 destroys such a temporary twice.
          WriteOrigin origin{"modbus", "10.0.0.5:50122"};
          reply = co_await router.forward(unit, pdu, "10.0.0.5", std::move(origin));
        },
        asio::detached);
    REQUIRE(run_until(io, [&] { return reply.has_value(); }));
    return std::move(*reply);
  }

  AuditTrail trail{""};
  asio::io_context io;
  FakeLine line{io.get_executor()};
  BusScheduler scheduler{io.get_executor(), line, "bus"};
  RequestRouter router{io.get_executor(), RouterOptions{}};
  int sent = 0;
};

}  // namespace

TEST_CASE("the router passes through only the unit ids a bus lists") {
  Plant plant(false);
  CHECK(plant.router.passes_through(30));
  CHECK_FALSE(plant.router.passes_through(31));
  CHECK_FALSE(plant.router.passes_through(0));
  const ForwardedReply nobody = plant.forward(31, {0x03, 0, 0, 0, 1});
  REQUIRE_FALSE(nobody.has_value());
  CHECK(nobody.error() == ModbusException::gateway_path_unavailable);
}

TEST_CASE("with writes off only reading functions pass through, the rest is 0x01 and never sent") {
  Plant plant(false);
  for (const Bytes& pdu : {Bytes{0x03, 0, 0, 0, 1}, Bytes{0x04, 0, 0, 0, 1}, Bytes{0x01, 0, 0, 0, 8},
                           Bytes{0x02, 0, 0, 0, 8}, Bytes{0x07}, Bytes{0x11},
                           Bytes{0x2B, 0x0E, 0x01, 0x00}}) {
    CAPTURE(int(pdu[0]));
    const ForwardedReply reply = plant.forward(30, pdu);
    REQUIRE(reply.has_value());
    CHECK(*reply == pdu);
  }
  CHECK(plant.sent == 7);
  for (const Bytes& pdu : {Bytes{0x06, 0, 0, 0, 1}, Bytes{0x10, 0, 0, 0, 1, 2, 0, 1},
                           Bytes{0x05, 0, 0, 0xFF, 0}, Bytes{0x08, 0, 1, 0, 0},
                           Bytes{0x17, 0, 0, 0, 1, 0, 0, 0, 1, 2, 0, 1}, Bytes{0x2B, 0x0D}}) {
    CAPTURE(int(pdu[0]));
    const ForwardedReply reply = plant.forward(30, pdu);
    REQUIRE_FALSE(reply.has_value());
    CHECK(reply.error() == ModbusException::illegal_function);
  }
  CHECK(plant.sent == 7);
}

TEST_CASE("with writes on every function passes through") {
  Plant plant(true);
  for (const Bytes& pdu : {Bytes{0x06, 0, 0, 0, 1}, Bytes{0x08, 0, 0, 0xA5, 0x37}, Bytes{0x41}}) {
    const ForwardedReply reply = plant.forward(30, pdu);
    REQUIRE(reply.has_value());
    CHECK(*reply == pdu);
  }
}

TEST_CASE("a bus that cannot take a forwarded request answers as its failure says") {
  CHECK(exception_for(ForwardFailure::busy) == ModbusException::busy);
  CHECK(exception_for(ForwardFailure::expired) == ModbusException::gateway_target_failed);
  CHECK(exception_for(ForwardFailure::no_response) == ModbusException::gateway_target_failed);
}

TEST_CASE("a relayed reply keeps the request's transaction, protocol and unit id") {
  const Bytes request{0x12, 0x34, 0x00, 0x00, 0x00, 0x06, 0x1E, 0x03, 0x00, 0x00, 0x00, 0x02};
  CHECK(relayed_reply(request, Bytes{0x03, 0x04, 0x00, 0x01, 0x00, 0x02}) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x07, 0x1E, 0x03, 0x04, 0x00, 0x01, 0x00, 0x02});
  CHECK(relayed_reply(request, Bytes{0x83, 0x02}) ==
        Bytes{0x12, 0x34, 0x00, 0x00, 0x00, 0x03, 0x1E, 0x83, 0x02});
  // The longest PDU: the length field's high byte too.
  const Bytes pdu(253, 0x41);
  const Bytes reply = relayed_reply(request, pdu);
  CHECK(reply.size() == 260);
  CHECK(reply[4] == 0x00);
  CHECK(reply[5] == 254);
}

TEST_CASE("a passed-through write is one audit record with who sent it and what the device answered, and a read none") {
  Plant plant(true);
  REQUIRE(plant.forward(30, {0x03, 0, 0, 0, 1}).has_value());
  CHECK(plant.trail.recent({}).empty());
  REQUIRE(plant.forward(30, {0x06, 0, 0, 0, 2}).has_value());
  plant.line.reply = [](const LineRequest&) { return Bytes{30, 0x90, 0x02}; };
  (void)plant.forward(30, {0x10, 0, 1, 0, 1, 2, 0, 7});
  const auto records = plant.trail.recent({});
  REQUIRE(records.size() == 2);
  CHECK(records[1] == AuditRecord{records[1].unix_ms, {"modbus", "10.0.0.5:50122"}, "bus/30",
                                  "function 06", "", "00000002", "ack"});
  CHECK(records[0].setting == "function 10");
  CHECK(records[0].new_value == "00010001020007");
  CHECK(records[0].result == "nak 0x02");
}

TEST_CASE("a passed-through write refused for [server] writes false is recorded as refused") {
  Plant plant(false);
  (void)plant.forward(30, {0x05, 0, 0, 0xFF, 0});
  const auto records = plant.trail.recent({});
  REQUIRE(records.size() == 1);
  CHECK(records[0].setting == "function 05");
  CHECK(records[0].result == "refused: [server] writes is false");
  CHECK(plant.sent == 0);
}
