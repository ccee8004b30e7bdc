#include "control/carried_change.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <chrono>

#include "driver/family.h"

namespace tiltgate::control {

std::optional<CarriedChange> change_asked(const ProtocolDescriptor& protocol,
                                          std::span<const std::uint8_t> request) {
  const std::optional<CarriedRequest> read =
      protocol.read_request ? protocol.read_request(request) : std::nullopt;
  if (read && !read->may_change) return std::nullopt;
  CarriedChange change;
  if (read) {
    change.address = read->address;
    change.function = read->function;
    change.data = read->data;
  } else {
    change.function = "bytes";
    change.data = fmt::format("{:02X}", fmt::join(request, ""));
  }
  return change;
}

std::int64_t now_unix_ms() {
  using namespace std::chrono;
  return duration_cast<milliseconds>(system_clock::now().time_since_epoch()).count();
}

bool same_request(const CarriedChange& a, const CarriedChange& b) {
  return a.address == b.address && a.function == b.function && a.data == b.data;
}

std::string carried_result(const ProtocolDescriptor& protocol, const CarriedEnd& ended,
                           bool expects_reply, std::span<const std::uint8_t> reply) {
  if (ended.busy) return "error: not sent, the bus did not get to it in time";
  if (ended.error) {
    if (*ended.error == LineError::timeout) return "timeout";
    return fmt::format("error: {}", to_string(*ended.error));
  }
  if (!expects_reply) return "sent, no reply expected";
  if (protocol.read_refusal)
    if (std::optional<std::string> refused = protocol.read_refusal(reply)) return *refused;
  return "ack";
}

}  // namespace tiltgate::control
