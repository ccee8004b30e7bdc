#include "sparkplug/host_state.h"

#include <nlohmann/json.hpp>
#include <optional>

namespace tiltgate::sparkplug {

Expected<HostState, std::string> parse_host_state(std::string_view text) {
  if (text.size() > kMaxHostStateBytes) {
    return Unexpected("a STATE payload of " + std::to_string(text.size()) + " bytes");
  }
  // Untrusted bytes from the broker: the parser's non-throwing form, and every value's type
  // checked before it is read.
  const nlohmann::json state = nlohmann::json::parse(text, nullptr, false);
  if (state.is_discarded() || !state.is_object()) {
    return Unexpected(std::string("a STATE payload is a JSON object"));
  }
  std::optional<bool> online;
  std::optional<std::uint64_t> timestamp;
  for (const auto& [key, value] : state.items()) {
    if (value.is_structured()) return Unexpected("the value of \"" + key + "\" is not a scalar");
    if (key == "online") {
      if (!value.is_boolean()) return Unexpected(std::string("\"online\" is not true or false"));
      online = value.get<bool>();
    } else if (key == "timestamp") {
      if (!value.is_number_unsigned()) {
        return Unexpected(std::string("\"timestamp\" is not a non-negative integer"));
      }
      timestamp = value.get<std::uint64_t>();
    }
  }
  if (!online) return Unexpected(std::string("no \"online\" key"));
  if (!timestamp) return Unexpected(std::string("no \"timestamp\" key"));
  return HostState{*online, *timestamp};
}

}  // namespace tiltgate::sparkplug
