#include "serial/low_latency.h"

#include <linux/serial.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <fstream>
#include <system_error>

#include <fmt/format.h>

namespace tiltgate {
namespace fs = std::filesystem;

namespace {

bool unsupported_errno(int error) { return error == ENOTTY || error == EINVAL; }

LowLatencyResult failure(int error) {
  return LowLatencyResult{unsupported_errno(error) ? LowLatencyOutcome::not_supported
                                                    : LowLatencyOutcome::failed,
                          error};
}

}  // namespace

const char* to_string(LowLatencyOutcome outcome) {
  switch (outcome) {
    case LowLatencyOutcome::set: return "set";
    case LowLatencyOutcome::already_set: return "already set";
    case LowLatencyOutcome::not_supported: return "not supported by this driver";
    case LowLatencyOutcome::failed: return "failed";
  }
  return "?";
}

std::string LowLatencyResult::describe() const {
  if (error == 0) {
    if (outcome == LowLatencyOutcome::not_supported)
      return "not supported by this driver (it did not keep the flag)";
    return to_string(outcome);
  }
  return fmt::format("{} ({})", to_string(outcome), std::generic_category().message(error));
}

LowLatencyResult set_low_latency(int fd) {
  serial_struct serial{};
  if (::ioctl(fd, TIOCGSERIAL, &serial) != 0) return failure(errno);
  if ((serial.flags & ASYNC_LOW_LATENCY) != 0) return {LowLatencyOutcome::already_set, 0};
  serial.flags |= ASYNC_LOW_LATENCY;
  if (::ioctl(fd, TIOCSSERIAL, &serial) != 0) return failure(errno);
  // Some drivers accept TIOCSSERIAL and drop the flags they do not know: look again.
  serial_struct kept{};
  if (::ioctl(fd, TIOCGSERIAL, &kept) != 0) return failure(errno);
  if ((kept.flags & ASYNC_LOW_LATENCY) == 0) return {LowLatencyOutcome::not_supported, 0};
  return {LowLatencyOutcome::set, 0};
}

std::string tty_kernel_name(const std::string& port) {
  std::error_code ec;
  const fs::path resolved = fs::canonical(port, ec);
  return (ec ? fs::path(port) : resolved).filename().string();
}

std::optional<int> read_latency_timer(const std::string& port, const fs::path& sysfs_root) {
  std::ifstream in(sysfs_root / "bus/usb-serial/devices" / tty_kernel_name(port) /
                   "latency_timer");
  int ms = 0;
  if (!(in >> ms)) return std::nullopt;
  return ms;
}

std::string latency_timer_path(const std::string& port) {
  std::string name = tty_kernel_name(port);
  // A port that is no ttyUSB (a pty, an on-board UART) gets the general form in the advice.
  if (name.rfind("ttyUSB", 0) != 0) name = "ttyUSBn";
  return "/sys/bus/usb-serial/devices/" + name + "/latency_timer";
}

bool is_usb_serial(const std::string& port, const fs::path& sysfs_root) {
  std::error_code ec;
  return fs::exists(sysfs_root / "bus/usb-serial/devices" / tty_kernel_name(port), ec);
}

LowLatencyLogLine low_latency_log_line(std::string_view name, const std::string& port,
                                       const LowLatencyResult& result,
                                       std::optional<int> latency_timer_ms, bool usb_serial) {
  using Level = LowLatencyLogLevel;
  const bool slow_timer = latency_timer_ms && *latency_timer_ms > 1;
  const std::string timer =
      slow_timer ? fmt::format("; its latency_timer is {} ms", *latency_timer_ms) : "";
  const std::string fix = fmt::format("echo 1 > {} (or a udev rule, see the README)",
                                      latency_timer_path(port));
  if (!usb_serial && !slow_timer) {
    // A pty or an on-board UART: no latency timer holds its bytes back, nothing to do.
    return {Level::debug, fmt::format("{}: {} low-latency flag: {} (not a USB serial adapter: "
                                      "no latency timer to set)",
                                      name, port, result.describe())};
  }
  switch (result.outcome) {
    case LowLatencyOutcome::set:
    case LowLatencyOutcome::already_set:
      return {slow_timer ? Level::warning : Level::info,
              fmt::format("{}: {} low-latency mode {}{}{}", name, port, result.describe(), timer,
                          slow_timer ? ", set it to 1: " + fix : "")};
    case LowLatencyOutcome::not_supported:
      return {slow_timer ? Level::warning : Level::info,
              fmt::format("{}: {} has no low-latency flag: {}{}; set the USB adapter's latency "
                          "timer to 1 ms instead: {}",
                          name, port, result.describe(), timer, fix)};
    case LowLatencyOutcome::failed: break;
  }
  return {Level::warning, fmt::format("{}: {} cannot be put in low-latency mode: {}{}; set its "
                                      "latency timer to 1 ms instead: {}",
                                      name, port, result.describe(), timer, fix)};
}

}  // namespace tiltgate
