// SerialLine's port: opening it with the bus's termios settings, and reopening it with
// back-off after it was lost (an unplugged adapter) or could not be opened. The exchange of
// requests and replies over it is serial_line.cpp's.
#include <fcntl.h>
#include <sys/file.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <system_error>

#include "serial/serial_line.h"

namespace tiltgate {

namespace asio = boost::asio;
using boost::system::error_code;

namespace {

std::string errno_text(int error) {
  return std::error_code(error, std::generic_category()).message();
}

}  // namespace

bool SerialLine::start() {
  if (stopped_ || port_.is_open()) return port_.is_open();
  auto opened = open_port();
  if (opened) {
    spdlog::info("{}: {} opened at {} baud", options_.name, options_.port, options_.baud);
    return true;
  }
  spdlog::warn("{}: cannot open {} ({}), retrying", options_.name, options_.port, opened.error());
  reopen_delay_ = options_.reopen_min;
  schedule_reopen();
  return false;
}

void SerialLine::stop() {
  stopped_ = true;
  reopen_timer_.cancel();
  quiet_timer_.cancel();
  error_code ignored;
  port_.close(ignored);  // a pending read or write completes with operation_aborted
}

std::optional<TtySettings> SerialLine::termios_in_force() {
  if (!port_.is_open()) return std::nullopt;
  auto settings = read_settings(port_.native_handle());
  if (!settings) return std::nullopt;
  return *settings;
}

Parity SerialLine::idle_parity() const {
  switch (options_.framing) {
    case Framing::eight_none_one: return Parity::none;
    case Framing::eight_even_one: return Parity::even;
    case Framing::eight_odd_one: return Parity::odd;
    case Framing::eight_none_two: return Parity::none;
    case Framing::nine_bit: return Parity::space;  // data bytes; address bytes switch to mark
  }
  return Parity::none;
}

Expected<Done, std::string> SerialLine::open_port() {
  // O_NONBLOCK: do not wait for a carrier, and let Asio drive the reads and writes.
  const int fd = ::open(options_.port.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return Unexpected(errno_text(errno));
  if (options_.exclusive && ::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EWOULDBLOCK) return Unexpected(std::string("in use: a tiltgate command holds it"));
    return Unexpected("cannot lock: " + errno_text(error));
  }
  auto configured =
      apply_raw_settings(fd, options_.baud, idle_parity(), stop_bits_of(options_.framing));
  if (!configured) {
    ::close(fd);
    return Unexpected("cannot configure: " + configured.error().message());
  }
  if (options_.low_latency) apply_low_latency(fd);
  if (options_.rs485_kernel) {
    auto rs485 = enable_kernel_rs485(fd);
    if (!rs485 && !warned_rs485_) {
      // Not fatal: USB adapters switch direction themselves and reject the ioctl.
      warned_rs485_ = true;
      spdlog::warn("{}: {} has no kernel RS485 mode ({}), continuing without it", options_.name,
                   options_.port, rs485.error().message());
    }
  }
  (void)discard_input(fd);  // whatever arrived before we were listening
  error_code ec;
  port_.assign(fd, ec);
  if (ec) {
    ::close(fd);
    return Unexpected(ec.message());
  }
  ++generation_;
  return Done{};
}

void SerialLine::apply_low_latency(int fd) {
  low_latency_ = set_low_latency(fd);
  // Read after setting it: ftdi_sio lowers the timer to 1 ms when the flag goes on.
  const LowLatencyLogLine line = low_latency_log_line(
      options_.name, options_.port, *low_latency_,
      read_latency_timer(options_.port, options_.sysfs_root),
      is_usb_serial(options_.port, options_.sysfs_root));
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

void SerialLine::schedule_reopen() {
  reopen_timer_.expires_after(reopen_delay_);
  reopen_timer_.async_wait([this, alive = std::weak_ptr<int>(alive_)](const error_code& ec) {
    if (ec || alive.expired()) return;
    reopen_now();
  });
}

void SerialLine::reopen_now() {
  if (stopped_ || port_.is_open()) return;
  auto opened = open_port();
  if (!opened) {
    reopen_delay_ = std::min(reopen_delay_ * 2, options_.reopen_max);
    spdlog::debug("{}: {} still unavailable ({}), next try in {} ms", options_.name,
                  options_.port, opened.error(), reopen_delay_.count());
    schedule_reopen();
    return;
  }
  reopen_delay_ = options_.reopen_min;
  if (generation_ > 1) {
    ++stats_.reopens;
    spdlog::info("{}: {} reopened", options_.name, options_.port);
  } else {
    spdlog::info("{}: {} opened at {} baud", options_.name, options_.port, options_.baud);
  }
}

void SerialLine::lose_port(const std::string& why) {
  ++stats_.io_errors;
  error_code ignored;
  port_.close(ignored);
  spdlog::warn("{}: {} lost ({}), reopening", options_.name, options_.port, why);
  reopen_delay_ = options_.reopen_min;
  schedule_reopen();
}

}  // namespace tiltgate
