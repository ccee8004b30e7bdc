// The control socket's messages: how a commissioning command (`tiltgate scan --via-gateway`...)
// has a running gateway run it on one of its buses. The command sends its request, the gateway
// runs the commissioning engine (commission/commission_events.h) on the bus between its polls
// and sends back what happens, one event at a time, and the command renders the events as it
// does those of a run on its own tty. Text lines, one message each, so a person can follow a
// session with socat. Pure formatting and parsing.
//
//   command -> gateway                      gateway -> command
//   version 3 0.1.0                         version 3 0.1.0          first, both: see below
//   hello /dev/ttyUSB0                      bus line1 PROTOCOL 125000
//                                           (or: error the gateway has no bus on /dev/ttyUSB0 ...)
//   run {"command":"scan",...}              event {"event":"progress",...}   as they happen
//                                           ...
//   stop                  (any time)        exit 0                   the command's exit code
//
// run: the command's options as JSON (commission_wire/command_request.h), read by the gateway as the
// command line reads them; one run a session, which ends with its exit line. stop: the engineer
// pressed Ctrl-C; the run ends as a stopped command does, with its exit line. A command that
// goes away (its socket closes) is stopped the same way.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "driver/expected.h"

namespace tiltgate::control {

// The longest line the gateway accepts from a command: a request's options fit many times over.
inline constexpr std::size_t kMaxLine = 4096;
// The longest line a command accepts from the gateway: an event, e.g. a scan's end with the
// table of every sensor found on a full bus.
inline constexpr std::size_t kMaxEventLine = 4 * 1024 * 1024;

inline constexpr unsigned kProtocolVersion = 3;

// Said by both sides: the protocol's number and the product's version ("0.1.0").
struct Version {
  unsigned protocol = 0;
  std::string product;
};
struct Hello {
  std::string port;  // the tty the command wants, or the bus's name
};
struct Run {
  std::string request;  // one JSON object
};
struct Stop {};
using CommandMessage = std::variant<Version, Hello, Run, Stop>;

struct BusGranted {
  std::string name;
  std::string protocol;
  std::uint32_t baud = 0;
};
struct Refused {
  std::string reason;
};
struct Event {
  std::string json;  // one JSON object
};
struct Exit {
  int code = 0;
};
using GatewayMessage = std::variant<Version, BusGranted, Refused, Event, Exit>;

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
