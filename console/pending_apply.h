// A configuration applied through the console that awaits its confirmation
// (docs/web-console.md, "Applying with a confirmation window"), kept on disk beside the served
// file as FILE.pending, so that a gateway restarted during the window still rolls back: the
// deadline is wall-clock time, the rollback target FILE.previous. Plain file work, no threads
// (console/confirm_window.h holds the timer).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "driver/expected.h"

namespace tiltgate {

struct PendingApply {
  std::int64_t deadline_unix_s = 0;  // system clock: survives a restart
  int confirm_s = 0;                 // the window it was given
  std::string user;                  // who applied it
  std::string changes;               // what it changed (the audit record's text)

  std::chrono::system_clock::time_point deadline() const {
    return std::chrono::system_clock::time_point(std::chrono::seconds(deadline_unix_s));
  }
};

std::string previous_file(const std::string& config_path);  // FILE.previous
std::string pending_file(const std::string& config_path);   // FILE.pending

// The one awaiting confirmation, when there is one. A marker that cannot be read as one has
// lost its deadline: it counts as due now, so the window's promise (roll back) still holds.
std::optional<PendingApply> read_pending(const std::string& config_path);
Expected<Done, std::string> write_pending(const std::string& config_path,
                                          const PendingApply& pending);
// The marker removed: the configuration is confirmed (or rolled back).
Expected<Done, std::string> remove_pending(const std::string& config_path);
// FILE.previous written back over FILE (its owner and mode kept), then the marker removed.
Expected<Done, std::string> restore_previous(const std::string& config_path);

}  // namespace tiltgate
