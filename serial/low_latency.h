// The tty driver's low-latency flag (ASYNC_LOW_LATENCY through TIOCGSERIAL/TIOCSSERIAL).
//
// Why: a USB-RS485 adapter's driver holds received bytes until its latency timer expires
// (16 ms by default on FTDI), which alone cuts a 125000-baud bus from ~420 to ~50 polls/s.
// With the flag set, ftdi_sio drops that timer to 1 ms. Drivers without it (pseudo-terminals,
// some USB adapters) say ENOTTY or EINVAL; an adapter that ignores the flag can still be told
// through sysfs: /sys/bus/usb-serial/devices/ttyUSBn/latency_timer.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace tiltgate {

enum class LowLatencyOutcome {
  set,            // the flag was off and is on now
  already_set,    // the flag was on already
  not_supported,  // the driver has no such flag (ENOTTY, EINVAL) or did not keep it
  failed,         // the driver has it but refused to change it (e.g. EPERM): errno
};

const char* to_string(LowLatencyOutcome outcome);

struct LowLatencyResult {
  LowLatencyOutcome outcome = LowLatencyOutcome::failed;
  int error = 0;  // errno of the failing ioctl; 0 when none failed

  // What happened, for a log line: "set", "not supported by this driver (...)", ...
  std::string describe() const;
  bool operator==(const LowLatencyResult&) const = default;
};

// Turns the flag on for the open tty `fd`, reading it back to see that the driver kept it.
// Never fails the caller: the outcome says what happened.
LowLatencyResult set_low_latency(int fd);

// The kernel's name of the tty at `port` once symlinks are followed: "ttyUSB0" for
// /dev/serial/by-id/usb-FTDI-...; the last part of the path as given when it cannot be followed.
std::string tty_kernel_name(const std::string& port);

// The USB serial driver's latency timer in ms, read from
// `sysfs_root`/bus/usb-serial/devices/<tty_kernel_name(port)>/latency_timer; nothing when the
// tty has none (not a USB serial adapter, or a driver without the attribute).
std::optional<int> read_latency_timer(const std::string& port,
                                      const std::filesystem::path& sysfs_root = "/sys");

// The sysfs file to write 1 into by hand or from a udev rule, for the log's advice.
std::string latency_timer_path(const std::string& port);

// Whether the tty at `port` is a USB serial adapter's (ftdi_sio, cp210x, ch341, pl2303, ...):
// `sysfs_root`/bus/usb-serial/devices/<tty_kernel_name(port)> exists. Only those have a latency
// timer; a pseudo-terminal, an on-board UART or a CDC-ACM device has none.
bool is_usb_serial(const std::string& port, const std::filesystem::path& sysfs_root = "/sys");

// The one log line for an open's outcome: what happened to `port` of bus `name`, the latency
// timer when it is above 1 ms, and what to do when the flag could not be set.
// - a warning when the bus is slowed for certain: a latency timer above 1 ms left as it is, or a
//   USB adapter that refused the flag;
// - info on a USB serial adapter otherwise, with the latency-timer advice where the flag is
//   missing: that is where it applies;
// - debug on any other tty (a pseudo-terminal, an on-board UART), which has no timer to set.
enum class LowLatencyLogLevel : std::uint8_t { debug, info, warning };
struct LowLatencyLogLine {
  LowLatencyLogLevel level = LowLatencyLogLevel::debug;
  std::string text;
};
LowLatencyLogLine low_latency_log_line(std::string_view name, const std::string& port,
                                       const LowLatencyResult& result,
                                       std::optional<int> latency_timer_ms, bool usb_serial);

}  // namespace tiltgate
