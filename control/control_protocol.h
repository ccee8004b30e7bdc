// The control socket's messages: how a commissioning command (`tiltgate info --via-gateway`...)
// borrows a running gateway's bus for one transaction at a time. Text lines, one message each,
// so a person can follow a session with socat. Pure formatting and parsing.
//
//   command -> gateway                      gateway -> command
//   version 2 0.1.0                         version 2 0.1.0          first, both: see below
//   hello /dev/ttyUSB0                      bus line1 PROTOCOL 125000
//                                           (or: error the gateway has no bus on /dev/ttyUSB0 ...)
//   transact 0 50 2 0 1 - 00DF0000000400..  reset                    before each attempt
//                                           bytes 0000DF00...        what the line received
//   more | done                             (the command's framer: is the reply whole?)
//                                           end ok 3 0 - 1           or: end timeout 0 - 1
//   hold 223                                ok line1/boom            (or: ok, none is there)
//   follow 223 7                            ok line1/boom            (or: ok, none was there)
//   release 223                             ok
//   setting 223 0 2                         ok line1/boom            (or: ok, none is there)
//   setting 223 0 2 nak 3 | ... timeout     ok line1/boom
//   as console user alice                   ok                       (or: error, not from you)
//
// setting: the sensor at 223 acknowledged a change of setting 0 (a WriteTarget id,
// driver/write_target.h) to 2; the gateway's settings record of the sensor follows it, as it
// does a Modbus write (SensorDriver::note_acknowledged). An address move is a follow instead.
// With "nak CODE" the sensor refused it, with "timeout" it did not answer: the gateway only
// records that in its audit trail (audit/audit_trail.h), as it records every setting and move.
// as: the session acts for someone else from now on, named in the audit trail instead of the
// socket's peer (the web console runs commands for its logged-in users); honoured only from a
// process of the gateway's own user.
// hold: the command is about to move the sensor at 223; the gateway stops polling it (a poll
// at the old address while it moves would fail and mark it offline) until follow or release,
// the session's end, or kMaxHold.
//
// transact: address bytes, time-out, retries, settle (ms), reply expected, late guard (ms, or -
// for the bus's own), the request in hex.
// The command keeps the framer, so the gateway needs no knowledge of the protocol: it moves the
// request's bytes on its line between polls and relays what comes back.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "driver/expected.h"
#include "driver/line.h"

namespace tiltgate::control {

// The longest line either side sends or accepts: a hex request of a few hundred bytes fits many
// times over.
inline constexpr std::size_t kMaxLine = 4096;

inline constexpr unsigned kProtocolVersion = 2;

// Said by both sides: the protocol's number and the product's version ("0.1.0").
struct Version {
  unsigned protocol = 0;
  std::string product;
};
struct Hello {
  std::string port;  // the tty the command wants, or the bus's name
};
struct Transact {
  std::size_t address_bytes = 0;
  std::chrono::milliseconds timeout{0};
  int retries = -1;
  std::chrono::milliseconds settle{0};
  bool expects_reply = true;
  std::optional<std::chrono::milliseconds> late_guard;  // none: the gateway's bus's own
  std::vector<std::uint8_t> bytes;
};
struct FramerAnswer {
  bool done = false;  // "done": the reply is whole; "more": keep reading
};
struct Follow {
  std::uint32_t from = 0;
  std::uint32_t to = 0;
};
struct Hold {
  std::uint32_t address = 0;
};
struct Release {
  std::uint32_t address = 0;
};
struct SettingChanged {
  std::uint32_t address = 0;
  std::uint8_t setting = 0;  // WriteTarget::id
  double value = 0;
  std::optional<std::uint8_t> nak;  // the sensor refused it, with this code
  bool timeout = false;             // the sensor did not answer
};
struct ActingFor {
  std::string who;  // "console user alice"
};
using CommandMessage = std::variant<Version, Hello, Transact, FramerAnswer, Follow, Hold,
                                    Release, SettingChanged, ActingFor>;

struct BusGranted {
  std::string name;
  std::string protocol;
  std::uint32_t baud = 0;
};
struct Refused {
  std::string reason;
};
struct Reset {};
struct Received {
  std::vector<std::uint8_t> bytes;
};
// How the transaction ended: done (the framer accepted a reply, or none was expected), or the
// Line's error; with the Line's timing and generation.
struct Ended {
  std::optional<LineError> error;  // none: done
  bool busy = false;               // never sent: the bus did not get to it in time
  LineTiming timing;
  std::uint64_t generation = 0;
};
struct Followed {
  std::string sensor;  // "bus/sensor" that moved; empty when no configured sensor was there
};
using GatewayMessage =
    std::variant<Version, BusGranted, Refused, Reset, Received, Ended, Followed>;

// Each without its trailing newline.
std::string format(const CommandMessage& message);
std::string format(const GatewayMessage& message);

// The one line that ends a session whose two ends speak different versions, naming both:
// `gateway` is the gateway's product version; `command` the command's version line, none for a
// command of protocol 1 (which sent no version). Sent by the gateway as it is, not as "error
// ...", so that a command of protocol 1 shows it.
std::string version_mismatch(std::string_view gateway, const std::optional<Version>& command);
// What a command of `command_product` says when a gateway of protocol 1 refused its version
// line (as a malformed message).
std::string older_gateway(std::string_view command_product);

// What is wrong with a line is the error, for the other side's log.
Expected<CommandMessage, std::string> parse_command(std::string_view line);
Expected<GatewayMessage, std::string> parse_gateway(std::string_view line);

}  // namespace tiltgate::control
