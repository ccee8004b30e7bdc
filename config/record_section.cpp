// [record]: each sensor's long record on the box (docs/configuration.md, "[record]";
// docs/monitoring.md, "The long record").
#include <fmt/format.h>

#include "config/sections.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

RecordConfig read_record(const toml::table& table, ErrorList& errors) {
  TableReader in(table, "record", errors);
  RecordConfig record;
  // Whole seconds that divide a day, so every UTC day starts an interval: 1 s .. 1 h.
  if (auto seconds = in.integer("interval_s", 1, 3600)) {
    if (86400 % *seconds != 0)
      in.error("interval_s", fmt::format("{} does not divide a day (86400 s): take 1, 5, 10, 30, "
                                         "60, 300, 600 or 3600, say", *seconds));
    else
      record.interval = std::chrono::seconds(*seconds);
  }
  // Ten years at most; 0 keeps the day being written only.
  if (auto days = in.integer("keep_days", 0, 3660)) record.keep_days = std::uint32_t(*days);
  in.reject_unknown_keys();
  return record;
}

}  // namespace tiltgate::config
