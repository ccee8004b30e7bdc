#include "doors/connection_admission.h"

namespace tiltgate {

namespace {

// Whether `a` gives way before `b`: those that give way first, then the one idle longer.
bool gives_way_before(const OpenConnection& a, const OpenConnection& b) {
  if (a.gives_way_first != b.gives_way_first) return a.gives_way_first;
  return a.idle_since < b.idle_since;
}

// The idle connection to give way first among those `eligible` admits.
template <class Eligible>
std::optional<std::size_t> idle_longest(std::span<const OpenConnection> open, Eligible eligible) {
  std::optional<std::size_t> found;
  for (std::size_t i = 0; i < open.size(); ++i) {
    if (!open[i].idle || !eligible(open[i])) continue;
    if (!found || gives_way_before(open[i], open[*found])) found = i;
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
