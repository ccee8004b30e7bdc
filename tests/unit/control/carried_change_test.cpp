// What the control socket records of a command's transaction (control/carried_change.h): a
// change as the bus's protocol reads it, bytes it cannot read as a change, and the outcome in
// the audit trail's words.
#include <doctest/doctest.h>

#include "control/carried_change.h"
#include "driver/family.h"

using namespace tiltgate;
using namespace tiltgate::control;

namespace {

// A protocol whose requests are [address, function, data...], function 1 a read, and whose
// refusals are [0xFF, code].
std::optional<CarriedRequest> read_toy(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < 2) return std::nullopt;
  return CarriedRequest{bytes[0], bytes[1] != 1, "function " + std::to_string(bytes[1]), "AA"};
}
std::optional<std::string> refusal_of_toy(std::span<const std::uint8_t> reply) {
  if (reply.size() == 2 && reply[0] == 0xFF) return "nak 0x0" + std::to_string(reply[1]);
  return std::nullopt;
}
ProtocolDescriptor toy() {
  ProtocolDescriptor protocol;
  protocol.read_request = read_toy;
  protocol.read_refusal = refusal_of_toy;
  return protocol;
}

const std::vector<std::uint8_t> kWrite{7, 6, 0xAA};

}  // namespace

TEST_CASE("a request the protocol reads as a change is one, a read is none, and bytes it cannot read are one") {
  const ProtocolDescriptor protocol = toy();
  const auto change = change_asked(protocol, kWrite);
  REQUIRE(change);
  CHECK(change->address == 7u);
  CHECK(change->function == "function 6");
  CHECK(change->data == "AA");
  CHECK_FALSE(change_asked(protocol, std::vector<std::uint8_t>{7, 1}));
  const auto unread = change_asked(protocol, std::vector<std::uint8_t>{0x3A});
  REQUIRE(unread);
  CHECK_FALSE(unread->address);
  CHECK(unread->function == "bytes");
  CHECK(unread->data == "3A");
  CHECK(same_request(*change, *change_asked(protocol, kWrite)));
  CHECK_FALSE(same_request(*change, *unread));
}

TEST_CASE("a carried change's result: ack, the device's refusal, timeout, or never sent") {
  const ProtocolDescriptor protocol = toy();
  const std::vector<std::uint8_t> ack{7, 6};
  const std::vector<std::uint8_t> nak{0xFF, 3};
  CHECK(carried_result(protocol, CarriedEnd{}, true, ack) == "ack");
  CHECK(carried_result(protocol, CarriedEnd{}, true, nak) == "nak 0x03");
  CHECK(carried_result(protocol, CarriedEnd{}, false, {}) == "sent, no reply expected");
  CarriedEnd timed_out;
  timed_out.error = LineError::timeout;
  CHECK(carried_result(protocol, timed_out, true, {}) == "timeout");
  CarriedEnd busy;
  busy.busy = true;
  CHECK(carried_result(protocol, busy, true, {}).starts_with("error: not sent"));
  CarriedEnd broken;
  broken.error = LineError::io;
  CHECK(carried_result(protocol, broken, true, {}).starts_with("error: "));
}
