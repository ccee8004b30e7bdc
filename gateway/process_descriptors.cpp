#include "gateway/process_descriptors.h"

#include <sys/resource.h>

#include <filesystem>
#include <system_error>

namespace tiltgate {

std::optional<ProcessDescriptors> process_descriptors() {
  namespace fs = std::filesystem;
  ProcessDescriptors descriptors;
  std::error_code ec;
  fs::directory_iterator entries("/proc/self/fd", ec);
  if (ec) return std::nullopt;
  // The iterator's own descriptor is among them; Prometheus's collector counts it too.
  for (; entries != fs::directory_iterator(); entries.increment(ec)) {
    if (ec) return std::nullopt;
    ++descriptors.open;
  }
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) == 0) descriptors.max = double(limit.rlim_cur);
  return descriptors;
}

}  // namespace tiltgate
