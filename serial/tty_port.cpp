#include "serial/tty_port.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <system_error>
#include <utility>

#include "driver/visible_text.h"

namespace tiltgate {

using boost::system::error_code;

namespace {

std::string errno_text(int error) {
  return std::error_code(error, std::generic_category()).message();
}

}  // namespace

TtyPort::TtyPort(boost::asio::any_io_executor executor, TtyPortOptions options,
                 std::function<void()> on_reopened)
    : options_(std::move(options)),
      on_reopened_(std::move(on_reopened)),
      stream_(executor),
      reopen_timer_(executor),
      probe_(executor) {
  // A zero back-off would spin; a maximum below the minimum would make no sense.
  options_.reopen_min = std::max(options_.reopen_min, std::chrono::milliseconds{1});
  options_.reopen_max = std::max(options_.reopen_max, options_.reopen_min);
  reopen_delay_ = options_.reopen_min;
}

bool TtyPort::open() {
  if (stopped_ || stream_.is_open()) return stream_.is_open();
  auto opened = open_now();
  if (opened) {
    spdlog::info("{}: {} opened at {} baud", options_.name, visible_text(options_.path),
                 options_.baud);
    return true;
  }
  spdlog::warn("{}: cannot open {} ({}), retrying", options_.name, visible_text(options_.path),
               opened.error());
  reopen_delay_ = options_.reopen_min;
  schedule_reopen();
  return false;
}

void TtyPort::stop() {
  stopped_ = true;
  reopen_timer_.cancel();
  probe_.stop();
  error_code ignored;
  stream_.close(ignored);  // a pending read or write completes with operation_aborted
}

std::optional<TtySettings> TtyPort::settings_in_force() {
  if (!stream_.is_open()) return std::nullopt;
  auto settings = read_settings(stream_.native_handle(), options_.termios_ioctl);
  if (!settings) return std::nullopt;
  return *settings;
}

Expected<std::size_t, std::string> TtyPort::write_now(std::span<const std::uint8_t> bytes) {
  for (;;) {  // the descriptor is non-blocking (open_now)
    const ssize_t written = ::write(stream_.native_handle(), bytes.data(), bytes.size());
    if (written >= 0) return std::size_t(written);
    if (errno == EAGAIN || errno == EWOULDBLOCK) return std::size_t{0};
    if (errno != EINTR) return Unexpected(errno_text(errno));
  }
}

std::optional<UartCounts> TtyPort::uart_counts() {
  if (!counts_uart_) return std::nullopt;
  auto counted = tiltgate::uart_counts(stream_.native_handle());
  if (!counted) {
    counts_uart_ = false;  // the driver cannot say: not asked on every attempt again
    return std::nullopt;
  }
  return *counted;
}

Expected<std::size_t, std::string> TtyPort::discard_input() {
  // What waits is counted first (a port that cannot say counts none), then dropped.
  int waiting = 0;
  if (::ioctl(stream_.native_handle(), FIONREAD, &waiting) != 0) waiting = 0;
  auto flushed = tiltgate::discard_input(stream_.native_handle());
  if (!flushed) return Unexpected(flushed.error().message());
  return std::size_t(std::max(waiting, 0));
}

Expected<std::size_t, std::string> TtyPort::take_input(std::vector<std::uint8_t>& into) {
  std::size_t taken = 0;
  std::uint8_t chunk[256];
  for (;;) {  // the descriptor is non-blocking (open_now)
    const ssize_t got = ::read(stream_.native_handle(), chunk, sizeof chunk);
    if (got > 0) {
      into.insert(into.end(), chunk, chunk + got);
      taken += std::size_t(got);
      continue;
    }
    if (got == 0 || errno == EAGAIN || errno == EWOULDBLOCK) return taken;
    if (errno != EINTR) return Unexpected(errno_text(errno));
  }
}

Expected<Done, std::string> TtyPort::switch_parity(Parity parity) {
  auto applied = apply_parity(stream_.native_handle(), parity, options_.termios_ioctl);
  if (!applied) return Unexpected(applied.error().message());
  return Done{};
}

Expected<Done, std::string> TtyPort::wait_until_sent() {
  auto drained = tiltgate::wait_until_sent(stream_.native_handle());
  if (!drained) return Unexpected(drained.error().message());
  return Done{};
}

Expected<Done, std::string> TtyPort::open_now() {
  // O_NONBLOCK: do not wait for a carrier, and let Asio drive the reads and writes.
  const int fd = ::open(options_.path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return Unexpected(errno_text(errno));
  if (options_.exclusive && ::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EWOULDBLOCK) return Unexpected(std::string("in use: a tiltgate command holds it"));
    return Unexpected("cannot lock: " + errno_text(error));
  }
  auto configured = apply_raw_settings(fd, options_.baud, options_.parity, options_.stop_bits,
                                       options_.termios_ioctl);
  if (!configured) {
    ::close(fd);
    return Unexpected("cannot configure: " +
                      settings_error_text(configured.error(), options_.baud));
  }
  if (*configured == TermiosInterface::standard_rates_only && !warned_no_termios2_) {
    // Once per line, not per reopen: the port stays what it is (docs/operations.md,
    // "A port without termios2").
    warned_no_termios2_ = true;
    spdlog::warn("{}: {} does not take termios2 (an old kernel, an emulator or its driver): set "
                 "to {} baud through TCSETS, which has the standard rates only",
                 options_.name, visible_text(options_.path), options_.baud);
  }
  if (options_.low_latency) apply_low_latency(fd);
  if (options_.rs485_kernel) {
    auto rs485 = enable_kernel_rs485(fd);
    if (!rs485 && !warned_rs485_) {
      // Not fatal: USB adapters switch direction themselves and reject the ioctl.
      warned_rs485_ = true;
      spdlog::warn("{}: {} has no kernel RS485 mode ({}), continuing without it", options_.name,
                   visible_text(options_.path), rs485.error().message());
    }
  }
  (void)tiltgate::discard_input(fd);  // whatever arrived before we were listening
  error_code ec;
  stream_.assign(fd, ec);
  if (ec) {
    ::close(fd);
    return Unexpected(ec.message());
  }
  ++generation_;
  return Done{};
}

void TtyPort::apply_low_latency(int fd) {
  low_latency_ = set_low_latency(fd);
  // Read after setting it: ftdi_sio lowers the timer to 1 ms when the flag goes on.
  const LowLatencyLogLine line = low_latency_log_line(
      options_.name, options_.path, *low_latency_,
      read_latency_timer(options_.path, options_.sysfs_root),
      is_usb_serial(options_.path, options_.sysfs_root));
  if (logged_low_latency_ == low_latency_) {
    spdlog::debug("{}", line.text);  // a reopen that ends as the last open did
    return;
  }
  logged_low_latency_ = low_latency_;
  switch (line.level) {
    case LowLatencyLogLevel::warning: spdlog::warn("{}", line.text); break;
    case LowLatencyLogLevel::info: spdlog::info("{}", line.text); break;
    case LowLatencyLogLevel::debug: spdlog::debug("{}", line.text); break;
  }
}

void TtyPort::schedule_reopen() {
  reopen_timer_.expires_after(reopen_delay_);
  reopen_timer_.async_wait([this, alive = std::weak_ptr<int>(alive_)](const error_code& ec) {
    if (ec || alive.expired()) return;
    reopen_now();
  });
}

void TtyPort::reopen_now() {
  if (stopped_ || stream_.is_open()) return;
  auto opened = open_now();
  if (!opened) {
    reopen_delay_ = std::min(reopen_delay_ * 2, options_.reopen_max);
    spdlog::debug("{}: {} still unavailable ({}), next try in {} ms", options_.name,
                  visible_text(options_.path), opened.error(), reopen_delay_.count());
    schedule_reopen();
    return;
  }
  reopen_delay_ = options_.reopen_min;
  if (generation_ > 1) {
    if (on_reopened_) on_reopened_();
    spdlog::info("{}: {} reopened", options_.name, visible_text(options_.path));
  } else {
    spdlog::info("{}: {} opened at {} baud", options_.name, visible_text(options_.path),
                 options_.baud);
  }
}

void TtyPort::lose(const std::string& why) {
  error_code ignored;
  stream_.close(ignored);
  spdlog::warn("{}: {} lost ({}), reopening", options_.name, visible_text(options_.path), why);
  reopen_delay_ = options_.reopen_min;
  schedule_reopen();
}

}  // namespace tiltgate
