// termios2 settings applied to, and read back from, the slave side of a pseudo-terminal.
// A pty keeps the baud rate, PARODD and CMSPAR as set, but always clears PARENB (Linux
// pty_set_termios), so the parity tests look at the stick/odd bits.
#include "serial/termios_settings.h"

#include <doctest/doctest.h>
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <string>
#include <utility>

#include "serial/pseudo_terminal.h"
#include "sim/support/termios2_skip.h"

using namespace std::chrono_literals;
using tiltgate::Parity;
using tiltgate::PseudoTerminal;
using tiltgate::TtySettings;
using tiltgate::test::skip_unless_settable;

namespace {

// The slave side, opened the way a serial line opens its port.
class SlaveFd {
 public:
  explicit SlaveFd(const std::string& path)
      : fd_(::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC)) {}
  ~SlaveFd() {
    if (fd_ >= 0) ::close(fd_);
  }
  SlaveFd(const SlaveFd&) = delete;
  SlaveFd& operator=(const SlaveFd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

PseudoTerminal open_pty() {
  auto pty = PseudoTerminal::open();
  REQUIRE_MESSAGE(pty.has_value(), (pty ? "" : pty.error()));
  return std::move(*pty);
}

TtySettings settings_of(int fd) {
  auto settings = tiltgate::read_settings(fd);
  REQUIRE(settings.has_value());
  return *settings;
}

bool readable(int fd, int timeout_ms) {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, timeout_ms) == 1 && (p.revents & POLLIN);
}

}  // namespace

TEST_CASE("every Rieker and Spectron baud rate is set and read back, standard or not") {
  PseudoTerminal pty = open_pty();
  SlaveFd fd(pty.slave_path());
  REQUIRE(fd.get() >= 0);
  for (std::uint32_t baud : {9600u, 19200u, 28800u, 38400u, 62500u, 115200u, 125000u, 128000u,
                             250000u}) {
    CAPTURE(baud);
    skip_unless_settable(baud);
    REQUIRE(tiltgate::apply_raw_settings(fd.get(), baud, Parity::none).has_value());
    const TtySettings s = settings_of(fd.get());
    CHECK(s.output_baud == baud);
    CHECK(s.input_baud == baud);
  }
}

TEST_CASE("raw settings give 8 data bits, 1 stop bit, no flow control and unchecked parity") {
  PseudoTerminal pty = open_pty();
  SlaveFd fd(pty.slave_path());
  REQUIRE(tiltgate::apply_raw_settings(fd.get(), 115200, Parity::none).has_value());
  const TtySettings s = settings_of(fd.get());
  CHECK(s.data_bits == 8);
  CHECK(s.stop_bits == 1);
  CHECK(s.raw);
  CHECK(s.receiver_on);
  CHECK_FALSE(s.flow_control);
  CHECK(s.ignores_parity_errors);
  CHECK_FALSE(s.checks_input_parity);
  CHECK(s.parity() == Parity::none);
}

TEST_CASE("two stop bits are set and read back, and one again after") {
  PseudoTerminal pty = open_pty();
  SlaveFd fd(pty.slave_path());
  REQUIRE(tiltgate::apply_raw_settings(fd.get(), 9600, Parity::none, 2).has_value());
  CHECK(settings_of(fd.get()).stop_bits == 2);
  CHECK(settings_of(fd.get()).data_bits == 8);
  REQUIRE(tiltgate::apply_raw_settings(fd.get(), 9600, Parity::even).has_value());
  CHECK(settings_of(fd.get()).stop_bits == 1);
}

TEST_CASE("each parity sets its stick and odd bits and keeps the rest") {
  PseudoTerminal pty = open_pty();
  SlaveFd fd(pty.slave_path());
  skip_unless_settable(38400, Parity::space);  // both stick parities
  REQUIRE(tiltgate::apply_raw_settings(fd.get(), 38400, Parity::mark).has_value());
  struct Bits {
    Parity parity;
    bool stick;
    bool odd;
  };
  for (Bits expected : {Bits{Parity::mark, true, true}, Bits{Parity::space, true, false},
                        Bits{Parity::odd, false, true}, Bits{Parity::even, false, false},
                        Bits{Parity::none, false, false}}) {
    CAPTURE(tiltgate::to_string(expected.parity));
    REQUIRE(tiltgate::apply_parity(fd.get(), expected.parity).has_value());
    const TtySettings s = settings_of(fd.get());
    CHECK(s.stick_parity == expected.stick);
    CHECK(s.odd_parity == expected.odd);
    CHECK(s.output_baud == 38400);
    CHECK(s.raw);
  }
}

TEST_CASE("the parity is decoded from PARENB, PARODD and CMSPAR") {
  TtySettings s;
  CHECK(s.parity() == Parity::none);
  s.parity_enabled = true;
  CHECK(s.parity() == Parity::even);
  s.odd_parity = true;
  CHECK(s.parity() == Parity::odd);
  s.stick_parity = true;
  CHECK(s.parity() == Parity::mark);
  s.odd_parity = false;
  CHECK(s.parity() == Parity::space);
  s.parity_enabled = false;
  CHECK(s.parity() == Parity::none);
}

TEST_CASE("baud 0 is refused instead of hanging up the line") {
  PseudoTerminal pty = open_pty();
  SlaveFd fd(pty.slave_path());
  auto set = tiltgate::apply_raw_settings(fd.get(), 0, Parity::none);
  REQUIRE_FALSE(set.has_value());
  CHECK(set.error() == std::errc::invalid_argument);
}

TEST_CASE("kernel RS485 mode fails cleanly on a pseudo-terminal") {
  PseudoTerminal pty = open_pty();
  SlaveFd fd(pty.slave_path());
  auto rs485 = tiltgate::enable_kernel_rs485(fd.get());
  REQUIRE_FALSE(rs485.has_value());
  // ENOTTY from the kernel's pty driver; qemu-user 7.2 refuses the ioctl itself, ENOSYS.
  CHECK((rs485.error() == std::errc::inappropriate_io_control_operation ||
         rs485.error() == std::errc::function_not_supported));
  CHECK(settings_of(fd.get()).receiver_on);  // the port is still usable
}

TEST_CASE("settings on something that is not a tty are errors, not crashes") {
  SlaveFd null_device("/dev/null");
  REQUIRE(null_device.get() >= 0);
  CHECK(tiltgate::read_settings(null_device.get()).error() ==
        std::errc::inappropriate_io_control_operation);
  CHECK_FALSE(tiltgate::apply_raw_settings(null_device.get(), 9600, Parity::none).has_value());
  CHECK(tiltgate::discard_input(-1).error() == std::errc::bad_file_descriptor);
  CHECK(tiltgate::wait_until_sent(-1).error() == std::errc::bad_file_descriptor);
}

TEST_CASE("discarding input drops what was received and not read") {
  PseudoTerminal pty = open_pty();
  SlaveFd fd(pty.slave_path());
  REQUIRE(tiltgate::apply_raw_settings(fd.get(), 115200, Parity::none).has_value());
  const char junk[] = "stale";
  REQUIRE(::write(pty.master_fd(), junk, sizeof junk) == sizeof junk);
  REQUIRE(readable(fd.get(), 2000));
  REQUIRE(tiltgate::discard_input(fd.get()).has_value());
  CHECK_FALSE(readable(fd.get(), 0));
}

TEST_CASE("waiting until sent returns on a pseudo-terminal") {
  PseudoTerminal pty = open_pty();
  SlaveFd fd(pty.slave_path());
  const char byte = 0x55;
  REQUIRE(::write(fd.get(), &byte, 1) == 1);
  CHECK(tiltgate::wait_until_sent(fd.get()).has_value());
}

TEST_CASE("wire time counts 10 bits a byte without parity and 11 with, rounded up") {
  using tiltgate::wire_time;
  CHECK(tiltgate::bits_per_byte(Parity::none) == 10);
  CHECK(tiltgate::bits_per_byte(Parity::mark) == 11);
  CHECK(tiltgate::bits_per_byte(Parity::none, 2) == 11);  // Modbus RTU 8N2
  CHECK(wire_time(3, 9600, Parity::none, 2) == 3438us);
  CHECK(wire_time(10, 125000, Parity::none) == 800us);  // Rieker: 8 us a byte
  CHECK(wire_time(1, 9600, Parity::mark) == 1146us);    // 1145.83 us
  CHECK(wire_time(3, 9600, Parity::even) == 3438us);    // 3437.5 us
  CHECK(wire_time(0, 9600, Parity::none) == 0us);
  CHECK(wire_time(5, 0, Parity::none) == 0us);
}

TEST_CASE("a pseudo-terminal cannot count UART errors, and says so instead of a count") {
  PseudoTerminal pty = open_pty();
  SlaveFd fd(pty.slave_path());
  const auto counts = tiltgate::uart_counts(fd.get());
  REQUIRE_FALSE(counts.has_value());
  CHECK(tiltgate::uart_counts(-1).error() == std::errc::bad_file_descriptor);
}
