// [server] allow and write_allow on the Modbus TCP server: a host outside allow is closed at
// accept; one outside write_allow reads but every write gets exception 01, passed-through units
// included. Clients bound to 127.0.0.2 are another host (loopback has all of 127.0.0.0/8).
#include <doctest/doctest.h>

#include <string>
#include <vector>

#include "sim/support/modbus_test_server.h"

using namespace tiltgate;
using namespace tiltgate::test;

namespace {

AddressAllowList only(std::vector<std::string> entries) {
  auto list = AddressAllowList::parse(entries);
  REQUIRE(list.has_value());
  return *list;
}

Bytes for_unit(Bytes frame, std::uint8_t unit) {
  frame[6] = unit;
  return frame;
}

}  // namespace

TEST_CASE("a host outside [server] allow is closed at accept, an allowed one is served") {
  ModbusServerOptions options = test_options();
  options.allow = only({"127.0.0.1"});
  RunningServer server(options);
  RawSocket stranger(server.port, "127.0.0.2");
  CHECK(stranger.closed_by_server());
  RawSocket plc(server.port, "127.0.0.1");
  CHECK(answered(plc, 1));
  const auto stats = server.stats();
  CHECK(stats.denied == 1);
  CHECK(stats.accepted == 1);
}

TEST_CASE("a host outside write_allow reads, but its writes get 01 and change nothing") {
  ModbusServerOptions options = test_options();
  options.write_allow = only({"127.0.0.1/32"});
  RunningServer server(options);
  RawSocket panel(server.port, "127.0.0.2");
  CHECK(answered(panel, 1));
  panel.send(write_holding_frame(2, 10, 77));
  CHECK(panel.receive(9) == Bytes{0x00, 0x02, 0x00, 0x00, 0x00, 0x03, 0x01, 0x86, 0x01});
  // Passed-through units too: the device never sees it.
  panel.send(for_unit(write_holding_frame(3, 10, 77), FakeHandler::kPassedUnit));
  CHECK(panel.receive(9) == Bytes{0x00, 0x03, 0x00, 0x00, 0x00, 0x03, 0x09, 0x86, 0x01});
  panel.send(read_holding_frame(4, 10));
  CHECK(panel.receive(11) == holding_reply(4, 1010));  // unchanged
  CHECK(server.stats().writes_denied == 2);

  RawSocket plc(server.port, "127.0.0.1");
  plc.send(write_holding_frame(5, 10, 77));
  CHECK(plc.receive(12) == write_holding_frame(5, 10, 77));
  panel.send(read_holding_frame(6, 10));
  CHECK(panel.receive(11) == holding_reply(6, 77));
  CHECK(server.stats().writes_denied == 2);
}
