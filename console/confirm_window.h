// The confirmation window of a configuration applied through the console, as a network switch's
// "commit confirmed" (docs/web-console.md, "Applying with a confirmation window"): the applied
// file is served at once, and unless POST /api/config/confirm arrives through it (the gateway
// has loaded it, and the request came to the console it serves) before the deadline, the
// previous file is restored and reloaded. The window is kept on disk (console/pending_apply.h),
// so a restart during it still rolls back. Owned by the composition root, not by the console's
// handler, which a changed [http] replaces.
//
// Threads: apply and confirm come from the HTTP thread; the deadline waits on a thread of its
// own, which restores the file and asks for the reload (SIGHUP), so neither the buses nor the
// console wait for the disk. One mutex orders them: an apply, a confirm and a rollback never
// overlap.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "audit/audit_trail.h"
#include "console/pending_apply.h"

namespace tiltgate {

class ConfirmWindow {
 public:
  // `reload`: asks the gateway to reload its file (as SIGHUP does), on any thread.
  ConfirmWindow(std::string config_path, AuditTrail* audit, std::function<void()> reload);
  // Stops the waiting thread; an open window stays on disk for the next start.
  ~ConfirmWindow();
  ConfirmWindow(const ConfirmWindow&) = delete;
  ConfirmWindow& operator=(const ConfirmWindow&) = delete;

  // At start-up, before the file is loaded: a window whose deadline passed while no gateway
  // watched it is rolled back now. Returns it, to be recorded once the trail is open.
  static std::optional<PendingApply> roll_back_if_due(const std::string& config_path);
  // Once the trail is open: records a rollback done at start-up, and arms again a window a
  // gateway before a restart left open, with its own deadline.
  void resume(const std::optional<PendingApply>& rolled_back_at_start);
  // The configuration under an open window could not be loaded or started: rolled back at
  // once, so the next start serves the previous file. False when no window was open.
  static bool roll_back_failed_start(const std::string& config_path);

  // PUT /api/config, once the text passed the check: the text written over the served file and
  // the window opened. FILE.previous is the last confirmed file: written now unless a window is
  // already open, whose rollback target stays (a second apply restarts the window).
  // `loads`: the gateway's Gateway::loads() when it was asked.
  Expected<Done, std::string> apply(const std::string& config_text, const PendingApply& pending,
                                    std::uint64_t loads);
  // POST /api/config/confirm, with Gateway::loads() as the request saw it: refused (why) while
  // the gateway has not loaded the applied file, or when nothing awaits confirmation.
  Expected<PendingApply, std::string> confirm(const std::string& user, std::uint64_t loads);
  std::optional<PendingApply> pending() const;

 private:
  void wait_for_deadlines();
  void roll_back(std::unique_lock<std::mutex>& lock);

  const std::string config_path_;
  AuditTrail* const audit_;
  const std::function<void()> reload_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<PendingApply> pending_;
  std::uint64_t loads_at_apply_ = 0;  // Gateway::loads() when applied; 0 after a restart
  bool stopping_ = false;
  std::thread waiter_;
};

}  // namespace tiltgate
