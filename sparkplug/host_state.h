// A Sparkplug Host Application's STATE message (Sparkplug 3.0.0, 4.2.3 "Sparkplug Host
// Application"): spBv1.0/STATE/<host_id> with the JSON {"online": true|false, "timestamp": ms}.
// An edge node with a primary host publishes its births only while that host is online. Pure.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "driver/expected.h"

namespace tiltgate::sparkplug {

struct HostState {
  bool online = false;
  std::uint64_t timestamp = 0;  // ms since the Unix epoch, when the host published it

  bool operator==(const HostState&) const = default;
};

// A host's STATE is some 50 bytes; a longer one is refused unread.
inline constexpr std::size_t kMaxHostStateBytes = 4096;

// The state in `json`: one flat JSON object with a Boolean "online" and a non-negative integer
// "timestamp" (other keys are allowed and ignored). Anything else, nested values included, is
// refused with the reason.
Expected<HostState, std::string> parse_host_state(std::string_view json);

}  // namespace tiltgate::sparkplug
