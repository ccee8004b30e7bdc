// One bus's tty, open or being reopened: owns the descriptor the SerialLine moves its bytes
// through. It knows no framing and no transaction, only how the port is opened and kept open.
//
// Opening: an advisory lock if asked, raw mode at the bus's baud, parity and stop bits
// (serial/termios_settings.h), then what was received before we were listening is dropped. A
// symlink (/dev/serial/by-id/...) is followed at every open, so an adapter that comes back as
// another ttyUSB is found again.
//
// Reopening: a port that could not be opened, or that the line lost (EIO from an unplugged
// adapter, a vanished device file), is retried in the background, the delay doubling from
// reopen_min to reopen_max; every successful open counts one generation. Nothing here throws
// or ends the process.
//
// Kernel RS485 (rs485_kernel): a port whose driver refuses TIOCSRS485 (USB adapters, ptys, ENOTTY;
// qemu-user, ENOSYS) logs one warning and is used as it is.
//
// A port that refuses termios2 is set through TCSETS at a standard rate (serial/termios_settings.h)
// and logs one warning, at its first open; at a rate with no standard code it does not open, and
// the reason names the rate.
//
// Low latency (low_latency, serial/low_latency.h): at every open the driver's ASYNC_LOW_LATENCY
// flag is set, so a USB adapter hands received bytes over at once instead of after its latency
// timer. The outcome is logged when it differs from the previous open's (an unplugged adapter
// that comes back the same stays quiet); a port that cannot take the flag is used as it is.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "driver/expected.h"
#include "serial/delivery_probe.h"
#include "serial/line_port.h"
#include "serial/low_latency.h"
#include "serial/termios_settings.h"

namespace tiltgate {

// How a bus's tty is opened and reopened: the port side of SerialLineOptions
// (serial/serial_line.h).
struct TtyPortOptions {
  std::string name;  // the bus's, for log lines
  std::string path;  // e.g. /dev/ttyUSB0
  std::uint32_t baud = 125000;
  Parity parity = Parity::none;  // in force between packets
  int stop_bits = 1;
  bool rs485_kernel = false;
  bool exclusive = false;  // flock the tty while it is open
  bool low_latency = true;
  std::string sysfs_root = "/sys";  // where a USB adapter's latency_timer is read for the log
  std::chrono::milliseconds reopen_min{500};
  std::chrono::milliseconds reopen_max{10000};
  // The settings' ioctl(2); a test's stand-in (ioctl_without_termios2) refuses termios2.
  IoctlCall termios_ioctl = system_ioctl;
};

class TtyPort final : public LinePort {
 public:
  // `on_reopened` is called after each successful open but the first (the line counts them).
  TtyPort(boost::asio::any_io_executor executor, TtyPortOptions options,
          std::function<void()> on_reopened);
  TtyPort(const TtyPort&) = delete;
  TtyPort& operator=(const TtyPort&) = delete;

  bool open() override;
  void stop() override;
  void lose(const std::string& why) override;

  bool is_open() const override { return stream_.is_open(); }
  bool stopped() const override { return stopped_; }
  std::uint64_t generation() const override { return generation_; }
  boost::asio::posix::stream_descriptor& stream() override { return stream_; }
  Expected<std::size_t, std::string> write_now(std::span<const std::uint8_t> bytes) override;
  // TCIFLUSH.
  Expected<std::size_t, std::string> discard_input() override;
  bool resume() override {
    stopped_ = false;
    return true;
  }
  // Non-blocking reads until the kernel holds nothing more.
  Expected<std::size_t, std::string> take_input(std::vector<std::uint8_t>& into) override;
  std::optional<UartCounts> uart_counts() override;
  // Stick parity through termios, and tcdrain (serial/termios_settings.h).
  Expected<Done, std::string> switch_parity(Parity parity) override;
  Expected<Done, std::string> wait_until_sent() override;
  std::optional<TtySettings> settings_in_force() override;
  const std::optional<LowLatencyResult>& low_latency() const override { return low_latency_; }
  DeliveryProbe* delivery_probe() override { return &probe_; }

 private:
  Expected<Done, std::string> open_now();
  void apply_low_latency(int fd);
  void schedule_reopen();
  void reopen_now();

  TtyPortOptions options_;
  std::function<void()> on_reopened_;
  boost::asio::posix::stream_descriptor stream_;
  boost::asio::steady_timer reopen_timer_;
  DeliveryProbe probe_;
  std::chrono::milliseconds reopen_delay_;
  bool stopped_ = false;
  bool counts_uart_ = true;  // until TIOCGICOUNT is refused once
  bool warned_rs485_ = false;
  bool warned_no_termios2_ = false;
  std::optional<LowLatencyResult> low_latency_;
  std::optional<LowLatencyResult> logged_low_latency_;  // the outcome last logged above debug
  std::uint64_t generation_ = 0;
  // Lets timer handlers that outlive the port see that it is gone.
  std::shared_ptr<int> alive_ = std::make_shared<int>(0);
};

}  // namespace tiltgate
