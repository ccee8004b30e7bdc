// The process's open file descriptors and its limit of them (RLIMIT_NOFILE), as /metrics shows
// them (process_open_fds, process_max_fds: the names of Prometheus's process collector), so a
// leak shows long before the limit refuses Modbus clients.
#pragma once

#include <optional>

namespace tiltgate {

struct ProcessDescriptors {
  double open = 0;
  double max = 0;  // the soft limit
};

// None where /proc/self/fd cannot be read.
std::optional<ProcessDescriptors> process_descriptors();

}  // namespace tiltgate
