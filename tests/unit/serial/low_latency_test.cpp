// The low-latency flag's outcome on descriptors that are no serial port, the latency timer
// read from a fake sysfs, and the log line each outcome gives (serial/low_latency.h).
#include <doctest/doctest.h>
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <fstream>
#include <string>

#include "serial/low_latency.h"
#include "unit/support/scratch_dir.h"

using namespace tiltgate;
using tiltgate::test::ScratchDir;
namespace fs = std::filesystem;

namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A fake sysfs root holding one USB serial tty's latency_timer.
void write_latency_timer(const ScratchDir& sysfs, const std::string& tty, const std::string& ms) {
  const fs::path dir = fs::path(sysfs.path("bus/usb-serial/devices")) / tty;
  fs::create_directories(dir);
  std::ofstream(dir / "latency_timer") << ms;
}

}  // namespace

TEST_CASE("low latency: a descriptor that is no tty is not supported (ENOTTY)") {
  const int null_fd = ::open("/dev/null", O_RDWR | O_CLOEXEC);
  REQUIRE(null_fd >= 0);
  CHECK(set_low_latency(null_fd) == LowLatencyResult{LowLatencyOutcome::not_supported, ENOTTY});
  ::close(null_fd);

  int pipe_fds[2];
  REQUIRE(::pipe(pipe_fds) == 0);
  const LowLatencyResult on_pipe = set_low_latency(pipe_fds[0]);
  CHECK(on_pipe.outcome == LowLatencyOutcome::not_supported);
  CHECK(on_pipe.error == ENOTTY);
  CHECK(contains(on_pipe.describe(), "not supported by this driver"));
  ::close(pipe_fds[0]);
  ::close(pipe_fds[1]);
}

TEST_CASE("low latency: a closed descriptor is a failure, with its errno") {
  const LowLatencyResult closed = set_low_latency(-1);
  CHECK(closed.outcome == LowLatencyOutcome::failed);
  CHECK(closed.error == EBADF);
  CHECK(contains(closed.describe(), "failed ("));
}

TEST_CASE("low latency: the latency timer is read under the tty's kernel name") {
  ScratchDir sysfs("tiltgate-sysfs");
  ScratchDir dev("tiltgate-dev");
  std::ofstream(dev.path("ttyUSB3")) << "";
  fs::create_symlink(dev.path("ttyUSB3"), dev.path("usb-FTDI_FT232R-if00-port0"));
  write_latency_timer(sysfs, "ttyUSB3", "16\n");

  // A by-id symlink is followed to the tty it names.
  CHECK(tty_kernel_name(dev.path("usb-FTDI_FT232R-if00-port0")) == "ttyUSB3");
  CHECK(read_latency_timer(dev.path("usb-FTDI_FT232R-if00-port0"), sysfs.path("")) == 16);
  CHECK(read_latency_timer(dev.path("ttyUSB3"), sysfs.path("")) == 16);
  CHECK(latency_timer_path(dev.path("ttyUSB3")) ==
        "/sys/bus/usb-serial/devices/ttyUSB3/latency_timer");
  // No such attribute: a pty, an on-board UART, a driver without it.
  CHECK_FALSE(read_latency_timer("/dev/ttyS0", sysfs.path("")).has_value());
  CHECK(latency_timer_path("/dev/pts/4") == "/sys/bus/usb-serial/devices/ttyUSBn/latency_timer");
}

TEST_CASE("low latency: the log line says what happened and the fix when the flag is missing") {
  using Level = LowLatencyLogLevel;
  const LowLatencyResult set{LowLatencyOutcome::set, 0};
  const LowLatencyLogLine fine = low_latency_log_line("line1", "/dev/ttyUSB0", set, 1, true);
  CHECK(fine.level == Level::info);
  CHECK(fine.text == "line1: /dev/ttyUSB0 low-latency mode set");

  // The flag went on but the timer stayed high: the bus is slow, say how to fix it.
  const LowLatencyLogLine slow = low_latency_log_line("line1", "/dev/ttyUSB0", set, 16, true);
  CHECK(slow.level == Level::warning);
  CHECK(contains(slow.text, "latency_timer is 16 ms"));
  CHECK(contains(slow.text, "echo 1 > /sys/bus/usb-serial/devices/ttyUSB0/latency_timer"));

  // A USB adapter whose driver has no flag: the latency-timer advice applies, at info.
  const LowLatencyResult missing{LowLatencyOutcome::not_supported, ENOTTY};
  const LowLatencyLogLine usb = low_latency_log_line("line1", "/dev/ttyUSB0", missing, 1, true);
  CHECK(usb.level == Level::info);
  CHECK(contains(usb.text, "line1: /dev/ttyUSB0 has no low-latency flag"));
  CHECK(contains(usb.text, "echo 1 > /sys/bus/usb-serial/devices/ttyUSB0/latency_timer"));
  CHECK(low_latency_log_line("line1", "/dev/ttyUSB0", missing, 16, true).level == Level::warning);

  const LowLatencyLogLine refused = low_latency_log_line(
      "line1", "/dev/ttyUSB0", LowLatencyResult{LowLatencyOutcome::failed, EPERM}, {}, true);
  CHECK(refused.level == Level::warning);
  CHECK(contains(refused.text, "cannot be put in low-latency mode: failed (Operation not permitted)"));
  CHECK(contains(refused.text, "echo 1 > /sys/bus/usb-serial/devices/ttyUSB0/latency_timer"));
}

TEST_CASE("low latency: a pty or an on-board UART gets one debug line and no USB advice") {
  using Level = LowLatencyLogLevel;
  const LowLatencyResult missing{LowLatencyOutcome::not_supported, ENOTTY};
  const LowLatencyLogLine pty = low_latency_log_line("line1", "/dev/pts/3", missing, {}, false);
  CHECK(pty.level == Level::debug);
  CHECK(contains(pty.text, "line1: /dev/pts/3 low-latency flag: not supported by this driver"));
  CHECK(contains(pty.text, "not a USB serial adapter"));
  CHECK_FALSE(contains(pty.text, "latency_timer"));
  CHECK_FALSE(contains(pty.text, "echo 1"));
  const LowLatencyLogLine uart = low_latency_log_line(
      "line1", "/dev/ttyS0", LowLatencyResult{LowLatencyOutcome::failed, EPERM}, {}, false);
  CHECK(uart.level == Level::debug);
  CHECK(low_latency_log_line("line1", "/dev/ttyS0", LowLatencyResult{LowLatencyOutcome::set, 0},
                             {}, false)
            .level == Level::debug);
}

TEST_CASE("low latency: a tty is a USB serial adapter's when sysfs lists it under usb-serial") {
  ScratchDir sysfs("tiltgate-usb-serial");
  write_latency_timer(sysfs, "ttyUSB3", "1\n");
  CHECK(is_usb_serial("/dev/ttyUSB3", sysfs.path("")));
  CHECK_FALSE(is_usb_serial("/dev/ttyS0", sysfs.path("")));
  CHECK_FALSE(is_usb_serial("/dev/pts/4", sysfs.path("")));
}
