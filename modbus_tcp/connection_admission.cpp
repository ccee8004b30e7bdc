#include "modbus_tcp/connection_admission.h"

namespace tiltgate {

namespace {

// The idle connection idle longest among those `eligible` admits.
template <class Eligible>
std::optional<std::size_t> idle_longest(std::span<const OpenConnection> open, Eligible eligible) {
  std::optional<std::size_t> found;
  for (std::size_t i = 0; i < open.size(); ++i) {
    if (!open[i].idle || !eligible(open[i])) continue;
    if (!found || open[i].idle_since < open[*found].idle_since) found = i;
  }
  return found;
}

}  // namespace

Admission admit_connection(std::span<const OpenConnection> open, std::string_view address,
                           AdmissionLimits limits) {
  std::size_t same_address = 0;
  for (const OpenConnection& c : open)
    if (c.address == address) ++same_address;
  if (same_address >= limits.max_clients_per_host) {
    // Its own connection only, so one host never displaces another's.
    const auto own = idle_longest(open, [&](const OpenConnection& c) { return c.address == address; });
    return Admission{own.has_value(), own, AdmissionLimit::max_clients_per_host};
  }
  if (open.size() >= limits.max_clients) {
    const auto any = idle_longest(open, [](const OpenConnection&) { return true; });
    return Admission{any.has_value(), any, AdmissionLimit::max_clients};
  }
  return Admission{true, std::nullopt, AdmissionLimit::none};
}

}  // namespace tiltgate
