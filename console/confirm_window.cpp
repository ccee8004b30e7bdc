#include "console/confirm_window.h"

#include <sys/stat.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "console/apply_audit.h"
#include "driver/visible_text.h"
#include "store/whole_file_write.h"
#include "toml/text_file.h"

namespace tiltgate {

namespace {

using SystemClock = std::chrono::system_clock;

bool due(const PendingApply& pending) { return pending.deadline() <= SystemClock::now(); }

}  // namespace

ConfirmWindow::ConfirmWindow(std::string config_path, AuditTrail* audit,
                             std::function<void()> reload)
    : config_path_(std::move(config_path)), audit_(audit), reload_(std::move(reload)) {
  waiter_ = std::thread([this] { wait_for_deadlines(); });
}

ConfirmWindow::~ConfirmWindow() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  waiter_.join();
}

std::optional<PendingApply> ConfirmWindow::roll_back_if_due(const std::string& config_path) {
  if (config_path.empty()) return std::nullopt;
  std::optional<PendingApply> pending = read_pending(config_path);
  if (!pending || !due(*pending)) return std::nullopt;
  spdlog::warn("{}: the configuration applied by {} was not confirmed before its deadline: "
               "restoring {}",
               config_path, visible_text(pending->user), previous_file(config_path));
  if (auto restored = restore_previous(config_path); !restored) {
    spdlog::error("the rollback failed: {}", restored.error());
    return std::nullopt;
  }
  return pending;
}

void ConfirmWindow::resume(const std::optional<PendingApply>& rolled_back_at_start) {
  if (rolled_back_at_start)
    record_rolled_back(audit_, *rolled_back_at_start,
                       "ok: not confirmed in time, restored at start-up");
  if (config_path_.empty()) return;
  std::optional<PendingApply> left_open = read_pending(config_path_);
  if (!left_open) return;
  {
    std::lock_guard lock(mutex_);
    pending_ = left_open;
    loads_at_apply_ = 0;  // this process loaded the applied file: confirmable at once
  }
  spdlog::warn("the configuration applied by {} awaits confirmation (POST /api/config/confirm) "
               "until {}: else {} is restored",
               visible_text(left_open->user), left_open->deadline_unix_s,
               previous_file(config_path_));
  changed_.notify_all();
}

bool ConfirmWindow::roll_back_failed_start(const std::string& config_path) {
  if (config_path.empty()) return false;
  const std::optional<PendingApply> pending = read_pending(config_path);
  if (!pending) return false;
  spdlog::error("the configuration applied by {} awaiting confirmation cannot be served: "
                "restoring {} for the next start",
                visible_text(pending->user), previous_file(config_path));
  if (auto restored = restore_previous(config_path); !restored)
    spdlog::error("the rollback failed: {}", restored.error());
  return true;
}

Expected<Done, std::string> ConfirmWindow::apply(const std::string& config_text,
                                                 const PendingApply& pending,
                                                 std::uint64_t loads) {
  std::unique_lock lock(mutex_);
  if (!pending_) {
    auto old = toml_input::read_text_file(config_path_);
    if (!old) return Unexpected{fmt::format("{}: {}", config_path_, old.error())};
    // FILE.previous takes the served file's mode, whatever an earlier one had (the
    // configuration may hold a broker's password: 0640 when the served file cannot be read);
    // the new file keeps the one it replaces.
    struct stat served {};
    const mode_t mode = ::stat(config_path_.c_str(), &served) == 0 ? served.st_mode & 07777 : 0640;
    if (auto kept = write_whole_file(previous_file(config_path_), *old, mode, FileMode::given);
        !kept)
      return kept;
  }
  // The marker before the file: a crash between them leaves a window over the old file, whose
  // rollback restores what is already there.
  if (auto marked = write_pending(config_path_, pending); !marked) return marked;
  if (auto written = write_whole_file(config_path_, config_text, 0640, FileMode::keep_old);
      !written) {
    if (!pending_) (void)remove_pending(config_path_);
    else (void)write_pending(config_path_, *pending_);
    return written;
  }
  pending_ = pending;
  loads_at_apply_ = loads;
  lock.unlock();
  changed_.notify_all();
  return Done{};
}

Expected<PendingApply, std::string> ConfirmWindow::confirm(const std::string& user,
                                                           std::uint64_t loads) {
  std::unique_lock lock(mutex_);
  if (!pending_) return Unexpected{std::string("no applied configuration awaits confirmation")};
  if (loads <= loads_at_apply_)
    return Unexpected{std::string(
        "the gateway has not loaded the applied configuration yet: confirm once it serves it")};
  if (auto removed = remove_pending(config_path_); !removed) return Unexpected{removed.error()};
  PendingApply confirmed = *pending_;
  pending_.reset();
  lock.unlock();
  changed_.notify_all();
  record_confirmed(audit_, user, confirmed);
  spdlog::info("the configuration applied by {} is confirmed by {}", visible_text(confirmed.user),
               visible_text(user));
  return confirmed;
}

std::optional<PendingApply> ConfirmWindow::pending() const {
  std::lock_guard lock(mutex_);
  return pending_;
}

void ConfirmWindow::wait_for_deadlines() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    if (!pending_) {
      changed_.wait(lock);
    } else if (due(*pending_)) {
      roll_back(lock);
    } else {
      changed_.wait_until(lock, pending_->deadline());
    }
  }
}

void ConfirmWindow::roll_back(std::unique_lock<std::mutex>& lock) {
  const PendingApply expired = *pending_;
  pending_.reset();
  auto restored = restore_previous(config_path_);
  lock.unlock();
  const std::string result =
      restored ? fmt::format("ok: not confirmed within {} s, previous file restored",
                             expired.confirm_s)
               : "error: " + restored.error();
  record_rolled_back(audit_, expired, result);
  if (restored) {
    spdlog::warn("the configuration applied by {} was not confirmed within {} s: {} restored "
                 "and reloaded",
                 visible_text(expired.user), expired.confirm_s, config_path_);
    if (reload_) reload_();
  } else {
    spdlog::error("the configuration applied by {} was not confirmed, and its rollback failed: {}",
                  visible_text(expired.user), restored.error());
  }
  lock.lock();
}

}  // namespace tiltgate
