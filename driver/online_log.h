// One log line when a sensor stops or starts answering, not one per poll.
#pragma once

#include <spdlog/spdlog.h>
#include <string_view>

namespace tiltgate {

inline void log_online_change(std::string_view sensor, std::string_view what, unsigned address,
                              std::string_view line, bool was_online, bool is_online) {
  if (was_online && !is_online) {
    spdlog::warn("{}: {} {} on {} stopped answering", sensor, what, address, line);
  } else if (!was_online && is_online) {
    spdlog::info("{}: {} {} on {} answering", sensor, what, address, line);
  }
}

}  // namespace tiltgate
