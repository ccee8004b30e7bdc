// The audit record of a command's transaction that may have changed a device, made from what
// the gateway carried and got back, never from what the command says it did (issue 52, item 3;
// docs/web-console.md, "The audit trail"). A command's line on a served bus carries its bytes without
// knowing what they mean: the bus's protocol reads them (ProtocolDescriptor::read_request), and
// bytes it cannot read count as a change. Pure.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "driver/line.h"
#include "driver/carried_request.h"

namespace tiltgate {

struct ProtocolDescriptor;

namespace control {

// A change a session's transaction carried, held by the session until it is recorded: a
// `setting` report or a `follow` right after it names it (one record), anything else records it
// as it is.
struct CarriedChange {
  std::optional<std::uint32_t> address;  // none: the protocol could not read the request
  std::string function;                  // "function 06", or "bytes" when unread
  std::string data;                      // in hex
  std::string result;                    // "ack", "nak 0x02", "timeout", "error: WHY", ...
  std::int64_t unix_ms = 0;              // when the result was known (the record may wait)
};

// What `request` asks, when it may change a device; none for a read. Its result is still to
// be filled in (carried_result()).
std::optional<CarriedChange> change_asked(const ProtocolDescriptor& protocol,
                                          std::span<const std::uint8_t> request);
// Whether both ask the same of the same device: a command's retry of a request.
bool same_request(const CarriedChange& a, const CarriedChange& b);
// When a result is known, wall clock, as the audit trail keeps it.
std::int64_t now_unix_ms();
// How a carried transaction ended: done, or the Line's error; `busy`: never sent, the bus did
// not get to it in time.
struct CarriedEnd {
  std::optional<LineError> error;
  bool busy = false;
};

// How the transaction ended, as the audit trail words it; `reply`: the bytes the line received
// in its last attempt (read for a refusal).
std::string carried_result(const ProtocolDescriptor& protocol, const CarriedEnd& ended,
                           bool expects_reply, std::span<const std::uint8_t> reply);

}  // namespace control
}  // namespace tiltgate
