#include "gateway/line_hint.h"

#include <fmt/format.h>

namespace tiltgate {

namespace {

// The sensor's failures over the recent window, or since start until that is counted.
FailureCounts recent_of(const SensorStatus& s) {
  return s.recent_failures ? *s.recent_failures : failure_counts(s);
}

bool behind_device_server(const BusStatus& bus) {
  return bus.port.starts_with("tcp://") || bus.port.starts_with("rfc2217://");
}

}  // namespace

std::optional<std::string> line_hint(const BusStatus& bus,
                                     const std::vector<SensorStatus>& sensors) {
  std::vector<const SensorStatus*> on_bus, garbled, silent;
  for (const SensorStatus& s : sensors) {
    if (s.bus != bus.name) continue;
    on_bus.push_back(&s);
    const FailureCounts recent = recent_of(s);
    if (recent.checksum_errors > 0) garbled.push_back(&s);
    if (recent.timeouts > 0) silent.push_back(&s);
  }
  if (on_bus.size() >= 2 && garbled.size() == on_bus.size())
    return std::string("Checksum errors on every device of this bus: check its baud rate, its "
                       "termination (120 ohm at both ends) and its bias.");
  if (garbled.size() == 1)
    return fmt::format("Checksum errors on {} only: check its drop cable, and that no second "
                       "device answers at its address {}.",
                       garbled.front()->name, garbled.front()->address);
  if (!on_bus.empty() && silent.size() == on_bus.size() && behind_device_server(bus) &&
      bus.reopens > 0)
    return std::string("Time-outs on every device since the serial device server reconnected: "
                       "check its packing delay (it should pass each frame on at once).");
  if (on_bus.size() >= 2 && silent.size() == 1)
    return fmt::format("{} does not answer while its neighbours do: check its power, its "
                       "address ({}) and its drop cable.",
                       silent.front()->name, silent.front()->address);
  return std::nullopt;
}

}  // namespace tiltgate
