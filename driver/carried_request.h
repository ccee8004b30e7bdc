// What a request a commissioning command puts on a gateway's line asks of a device, read from
// its bytes alone by the bus's protocol (ProtocolDescriptor::read_request): the control socket
// relays a command's bytes without knowing what they mean (control/control_protocol.h), yet
// records in the audit trail every one that may change a device, from what it carried and got
// back (docs/web-console.md, "The audit trail"). Plain data.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace tiltgate {

struct CarriedRequest {
  std::uint32_t address = 0;  // the device it addresses (a broadcast's own address)
  // False only for what the protocol's documents say reads, or only opens a write (a lock
  // that a change needs first): anything else, and anything unknown, may change the device.
  bool may_change = true;
  // As the trail words them, as it does a pass-through's (gateway/pass_through_audit.h): the
  // setting "function 06" or "function 41 (set filter)", the new value the data in hex.
  std::string function;
  std::string data;
};

// What a protocol reads from bytes on its line. `request` as the Line sends it (a 9-bit
// protocol's address byte first). None: the bytes are no request of the protocol, recorded as
// bytes that may change a device.
using ReadRequest = std::optional<CarriedRequest> (*)(std::span<const std::uint8_t> request);
// "nak 0x03" when `reply` is the device's refusal of the request; none for any other reply.
using ReadRefusal = std::optional<std::string> (*)(std::span<const std::uint8_t> reply);
// What `reply` says as the answer to `request`, decoded, in a few words, for the console's
// traffic view: "x 1.25 deg, y -0.5 deg", "values 4, 1", "ack". None when the bytes are no
// good answer to that request, or a refusal (ReadRefusal says that).
using ReadReply = std::optional<std::string> (*)(std::span<const std::uint8_t> request,
                                                 std::span<const std::uint8_t> reply);

}  // namespace tiltgate
