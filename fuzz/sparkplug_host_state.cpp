// The Sparkplug primary host's STATE reader (sparkplug/host_state.h): any bytes a broker
// delivers on spBv1.0/STATE/<host_id> are parsed without a throw escaping, and whatever it
// accepts reads back the same from the plain {"online": ..., "timestamp": ...} it stands for.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz/chunks.h"
#include "sparkplug/host_state.h"

using tiltgate::fuzz::check;
using tiltgate::sparkplug::HostState;
using tiltgate::sparkplug::parse_host_state;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto state = parse_host_state(std::string_view(reinterpret_cast<const char*>(data), size));
  if (!state) {
    check(!state.error().empty());  // a refusal says why
    return 0;
  }
  check(size <= tiltgate::sparkplug::kMaxHostStateBytes);
  const std::string plain = std::string("{\"online\":") + (state->online ? "true" : "false") +
                            ",\"timestamp\":" + std::to_string(state->timestamp) + "}";
  const auto again = parse_host_state(plain);
  check(again.has_value() && *again == *state);
  return 0;
}
