// The simulated line's collision rule on made-up timelines: when masters' bytes and devices'
// sends cross the line, which of them collide, and how often that is counted.
#include "serial/shared_wire.h"

#include <doctest/doctest.h>

using namespace tiltgate;
using namespace std::chrono_literals;

namespace {

using Bytes = std::vector<std::uint8_t>;

const WireClock::time_point t0{std::chrono::seconds(100)};

}  // namespace

TEST_CASE("a line with one master hands its bytes on at once and never breaks them") {
  SharedWire wire(1);
  CHECK(wire.transmit(0, t0, 10ms, Bytes{1, 2}, true) == t0);
  // A device's send on the line at the same time is not the master's concern there.
  CHECK(wire.schedule(WireSend{t0 - 1ms, t0 + 5ms, Bytes{0xAA}}));
  const auto crossed = wire.take_crossed(0, t0);
  REQUIRE(crossed.has_value());
  CHECK(crossed->bytes == Bytes{1, 2});
  CHECK(crossed->heard == Bytes{1, 2});
  CHECK_FALSE(crossed->broken);
  CHECK(wire.take_next().bytes == Bytes{0xAA});
  CHECK(wire.collisions() == 0);
}

TEST_CASE("a master's bytes cross the line in their wire time, after its own earlier bytes") {
  SharedWire wire(2);
  CHECK(wire.transmit(0, t0, 5ms, Bytes{1, 2}, true) == t0 + 5ms);
  CHECK(wire.transmit(0, t0 + 1ms, 5ms, Bytes{3}, true) == t0 + 10ms);
  CHECK_FALSE(wire.take_crossed(0, t0 + 9ms).has_value());
  const auto crossed = wire.take_crossed(0, t0 + 10ms);
  REQUIRE(crossed.has_value());
  CHECK(crossed->bytes == Bytes{1, 2, 3});
  CHECK_FALSE(crossed->broken);
  CHECK_FALSE(wire.take_crossed(0, t0 + 10ms).has_value());
  CHECK(wire.collisions() == 0);
}

TEST_CASE("bytes sent at a rate the devices do not hear cross the line but reach no device") {
  SharedWire wire(2);
  wire.transmit(1, t0, 1ms, Bytes{1}, false);
  wire.transmit(1, t0, 1ms, Bytes{2}, true);
  const auto crossed = wire.take_crossed(1, t0 + 2ms);
  REQUIRE(crossed.has_value());
  CHECK(crossed->bytes == Bytes{1, 2});
  CHECK(crossed->heard == Bytes{2});
}

TEST_CASE("two masters on the line at once both arrive inverted, counted as one collision") {
  SharedWire wire(2);
  wire.transmit(0, t0, 5ms, Bytes{0x01, 0x02}, true);
  wire.transmit(1, t0 + 2ms, 5ms, Bytes{0x10}, true);
  wire.transmit(1, t0 + 3ms, 5ms, Bytes{0x20}, true);  // the same collision, going on
  CHECK(wire.collisions() == 1);
  CHECK(wire.master_collisions() == 1);
  const auto first = wire.take_crossed(0, t0 + 5ms);
  const auto second = wire.take_crossed(1, t0 + 12ms);
  REQUIRE(first.has_value());
  REQUIRE(second.has_value());
  CHECK(first->broken);
  CHECK(first->bytes == Bytes{0xFE, 0xFD});
  CHECK(first->heard.empty());
  CHECK(second->broken);
  CHECK(second->bytes == Bytes{0xEF, 0xDF});
}

TEST_CASE("a master that starts once the other's bytes have crossed does not collide") {
  SharedWire wire(2);
  wire.transmit(0, t0, 5ms, Bytes{1}, true);
  REQUIRE(wire.take_crossed(0, t0 + 5ms).has_value());
  wire.transmit(1, t0 + 5ms, 5ms, Bytes{2}, true);
  const auto crossed = wire.take_crossed(1, t0 + 10ms);
  REQUIRE(crossed.has_value());
  CHECK_FALSE(crossed->broken);
  CHECK(wire.collisions() == 0);
}

TEST_CASE("a master that talks while a device's send is on the line breaks both") {
  SharedWire wire(2);
  CHECK(wire.schedule(WireSend{t0 + 10ms, t0 + 20ms, Bytes{0xAA}}));
  wire.transmit(1, t0 + 15ms, 2ms, Bytes{0x01}, true);
  CHECK(wire.collisions() == 1);
  CHECK(wire.master_collisions() == 1);
  const WireSend send = wire.take_next();
  CHECK(send.broken);
  CHECK(send.bytes == Bytes{0x55});
  const auto crossed = wire.take_crossed(1, t0 + 17ms);
  REQUIRE(crossed.has_value());
  CHECK(crossed->broken);
}

TEST_CASE("a device's send that starts while a master is transmitting breaks both") {
  SharedWire wire(2);
  wire.transmit(0, t0, 10ms, Bytes{0x01}, true);
  wire.schedule(WireSend{t0 + 5ms, t0 + 6ms, Bytes{0x0F}});
  CHECK(wire.collisions() == 1);
  CHECK(wire.master_collisions() == 1);
  CHECK(wire.take_next().bytes == Bytes{0xF0});
  CHECK(wire.take_crossed(0, t0 + 10ms)->broken);
}

TEST_CASE("a device's answer after the request has crossed does not collide with it") {
  SharedWire wire(2);
  wire.transmit(0, t0, 5ms, Bytes{0x01}, true);
  REQUIRE(wire.take_crossed(0, t0 + 5ms).has_value());
  wire.schedule(WireSend{t0 + 5ms, t0 + 8ms, Bytes{0x0F}});
  CHECK_FALSE(wire.take_next().broken);
  CHECK(wire.collisions() == 0);
}

TEST_CASE("devices' sends that overlap are each inverted once, and each newcomer counted") {
  SharedWire wire(1);
  wire.schedule(WireSend{t0, t0 + 10ms, Bytes{0x11}});
  wire.schedule(WireSend{t0 + 5ms, t0 + 8ms, Bytes{0x22}});
  wire.schedule(WireSend{t0 + 6ms, t0 + 9ms, Bytes{0x33}});  // meets both, already broken
  CHECK(wire.collisions() == 2);
  CHECK(wire.master_collisions() == 0);
  CHECK(wire.take_next().bytes == Bytes{0xDD});
  CHECK(wire.take_next().bytes == Bytes{0xCC});
  CHECK(wire.take_next().bytes == Bytes{0xEE});
}

TEST_CASE("a device's send that starts before the last one written was due is broken") {
  SharedWire wire(1);
  wire.schedule(WireSend{t0, t0 + 10ms, Bytes{0x11}});
  CHECK_FALSE(wire.take_next().broken);
  wire.schedule(WireSend{t0 + 5ms, t0 + 12ms, Bytes{0x22}});
  CHECK(wire.take_next().bytes == Bytes{0xDD});
  CHECK(wire.collisions() == 1);
}

TEST_CASE("sends are taken in the order they are due, and the first due is said") {
  SharedWire wire(1);
  CHECK(wire.schedule(WireSend{t0 + 50ms, t0 + 50ms, Bytes{'a'}}));
  CHECK(wire.schedule(WireSend{t0, t0, Bytes{'b'}}));
  CHECK_FALSE(wire.schedule(WireSend{t0 + 60ms, t0 + 60ms, Bytes{'c'}}));
  CHECK(wire.next_due() == t0);
  CHECK(wire.take_next().bytes == Bytes{'b'});
  CHECK(wire.take_next().bytes == Bytes{'a'});
  CHECK(wire.take_next().bytes == Bytes{'c'});
  CHECK_FALSE(wire.has_sends());
}
