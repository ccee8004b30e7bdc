// A port that refuses termios2 (an old kernel, an emulator such as qemu-user 7.2, an odd USB
// driver), stood in for on a pseudo-terminal by ioctl_without_termios2: the settings go through
// TCGETS/TCSETS with the standard rates' codes, read back here with glibc's tcgetattr, and a
// rate with no code is refused with an error that names it.
#include <doctest/doctest.h>
#include <fcntl.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <boost/asio/io_context.hpp>
#include <cerrno>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "serial/pseudo_terminal.h"
#include "serial/termios_settings.h"
#include "serial/tty_port.h"
#include "sim/support/captured_log.h"
#include "sim/support/termios2_skip.h"

using namespace std::chrono_literals;
using tiltgate::IoctlCall;
using tiltgate::Parity;
using tiltgate::PseudoTerminal;
using tiltgate::TermiosInterface;

namespace {

PseudoTerminal open_pty() {
  auto pty = PseudoTerminal::open();
  REQUIRE_MESSAGE(pty.has_value(), (pty ? "" : pty.error()));
  return std::move(*pty);
}

termios read_back(int fd) {
  termios t{};
  REQUIRE(::tcgetattr(fd, &t) == 0);
  return t;
}

// As qemu-user 7.2: no termios2, and TCSETS passes on the rate and flags it can translate but
// drops CMSPAR. glibc's struct termios starts with the kernel's four flag words.
int ioctl_like_qemu(int fd, unsigned long request, void* argument) {
  if (request == TCSETS) static_cast<termios*>(argument)->c_cflag &= ~tcflag_t(CMSPAR);
  return tiltgate::ioctl_without_termios2(fd, request, argument);
}

std::size_t lines_containing(const std::vector<std::string>& lines, const std::string& text) {
  std::size_t count = 0;
  for (const std::string& line : lines) count += line.find(text) != std::string::npos;
  return count;
}

// A bus's port on `path` whose settings go through ioctl_without_termios2.
tiltgate::TtyPortOptions port_without_termios2(const std::string& path, std::uint32_t baud) {
  tiltgate::TtyPortOptions options;
  options.name = "bus1";
  options.path = path;
  options.baud = baud;
  options.low_latency = false;
  options.reopen_min = 5ms;
  options.reopen_max = 5ms;
  options.termios_ioctl = tiltgate::ioctl_without_termios2;
  return options;
}

}  // namespace

TEST_CASE("a port without termios2 is set to each standard rate through TCSETS") {
  PseudoTerminal pty = open_pty();
  const int fd = pty.slave_fd();
  struct Rate {
    std::uint32_t baud;
    speed_t code;
  };
  for (Rate rate : {Rate{1200, B1200}, Rate{9600, B9600}, Rate{19200, B19200},
                    Rate{38400, B38400}, Rate{57600, B57600}, Rate{115200, B115200},
                    Rate{230400, B230400}, Rate{460800, B460800}, Rate{921600, B921600},
                    Rate{4000000, B4000000}}) {
    CAPTURE(rate.baud);
    tiltgate::test::skip_unless_settable(rate.baud);  // qemu 7.2 keeps none above 460800
    auto applied = tiltgate::apply_raw_settings(fd, rate.baud, Parity::even, 2,
                                                tiltgate::ioctl_without_termios2);
    REQUIRE_MESSAGE(applied.has_value(), (applied ? "" : applied.error().message()));
    CHECK(*applied == TermiosInterface::standard_rates_only);
    const termios t = read_back(fd);
    CHECK(::cfgetospeed(&t) == rate.code);
    CHECK(::cfgetispeed(&t) == rate.code);
    CHECK((t.c_cflag & CSTOPB) != 0);
    CHECK((t.c_cflag & CSIZE) == CS8);
    CHECK((t.c_lflag & ICANON) == 0);
    auto settings = tiltgate::read_settings(fd, tiltgate::ioctl_without_termios2);
    REQUIRE(settings.has_value());
    CHECK(settings->output_baud == rate.baud);
    CHECK(settings->input_baud == rate.baud);
    CHECK(settings->stop_bits == 2);
  }
}

TEST_CASE("a port with termios2 is still set through it") {
  PseudoTerminal pty = open_pty();
  auto applied = tiltgate::apply_raw_settings(pty.slave_fd(), 9600, Parity::none);
  REQUIRE(applied.has_value());
  if (*applied == TermiosInterface::standard_rates_only) {
    FAIL("skipped without termios2: this machine's ptys refuse it (an emulator?)");
  }
  CHECK(*applied == TermiosInterface::termios2);
}

TEST_CASE("a port without termios2 refuses 125000 baud with an error naming the rate and why") {
  PseudoTerminal pty = open_pty();
  const int fd = pty.slave_fd();
  REQUIRE(tiltgate::apply_raw_settings(fd, 9600, Parity::none, 1,
                                       tiltgate::ioctl_without_termios2).has_value());
  for (std::uint32_t baud : {125000u, 62500u, 28800u}) {
    CAPTURE(baud);
    auto applied = tiltgate::apply_raw_settings(fd, baud, Parity::none, 1,
                                                tiltgate::ioctl_without_termios2);
    REQUIRE_FALSE(applied.has_value());
    CHECK(tiltgate::needs_termios2(applied.error()));
    CHECK(tiltgate::settings_error_text(applied.error(), baud) ==
          "this port does not take termios2 (an old kernel, an emulator or its driver): " +
              std::to_string(baud) + " baud has no standard code");
    const termios now = read_back(fd);
    CHECK(::cfgetospeed(&now) == B9600);  // unchanged
  }
}

TEST_CASE("a port without termios2 switches parity through TCSETS") {
  tiltgate::test::skip_unless_settable(38400, Parity::space);  // qemu 7.2 drops CMSPAR
  PseudoTerminal pty = open_pty();
  const int fd = pty.slave_fd();
  REQUIRE(tiltgate::apply_raw_settings(fd, 38400, Parity::space, 1,
                                       tiltgate::ioctl_without_termios2).has_value());
  REQUIRE(tiltgate::apply_parity(fd, Parity::mark, tiltgate::ioctl_without_termios2).has_value());
  const termios t = read_back(fd);
  CHECK((t.c_cflag & CMSPAR) != 0);
  CHECK((t.c_cflag & PARODD) != 0);
  CHECK(::cfgetospeed(&t) == B38400);
}

TEST_CASE("a port that drops mark and space parity is an error, not a line at the wrong parity") {
  PseudoTerminal pty = open_pty();
  const int fd = pty.slave_fd();
  auto applied = tiltgate::apply_raw_settings(fd, 38400, Parity::space, 1, ioctl_like_qemu);
  REQUIRE_FALSE(applied.has_value());
  CHECK(tiltgate::settings_error_text(applied.error(), 38400) ==
        "this port does not take termios2 (an old kernel, an emulator or its driver): it dropped "
        "the mark/space parity bit (CMSPAR) that 9-bit framing needs");
  CHECK(tiltgate::apply_raw_settings(fd, 38400, Parity::even, 1, ioctl_like_qemu).has_value());
  CHECK_FALSE(tiltgate::apply_parity(fd, Parity::mark, ioctl_like_qemu).has_value());
}

TEST_CASE("a line on a port without termios2 opens at a standard rate and says so once") {
  PseudoTerminal pty = open_pty();
  boost::asio::io_context io;
  tiltgate::test::CapturedLog log(spdlog::level::info);
  tiltgate::TtyPort port(io.get_executor(), port_without_termios2(pty.slave_path(), 19200), {});
  REQUIRE(port.open());
  port.lose("unplugged");
  for (int i = 0; i < 200 && !port.is_open(); ++i) io.run_for(5ms);
  REQUIRE(port.is_open());
  CHECK(port.generation() == 2);
  const auto warnings = log.starting_with("warning ");
  CHECK(lines_containing(warnings, "bus1: " + pty.slave_path() +
                                       " does not take termios2 (an old kernel, an emulator or "
                                       "its driver): set to 19200 baud through TCSETS") == 1);
  port.stop();
}

TEST_CASE("a line at 125000 baud on a port without termios2 does not open, and says why") {
  PseudoTerminal pty = open_pty();
  boost::asio::io_context io;
  tiltgate::test::CapturedLog log(spdlog::level::info);
  tiltgate::TtyPort port(io.get_executor(), port_without_termios2(pty.slave_path(), 125000), {});
  CHECK_FALSE(port.open());
  CHECK(lines_containing(log.starting_with("warning "),
                         "cannot configure: this port does not take termios2 (an old kernel, an "
                         "emulator or its driver): 125000 baud has no standard code") == 1);
  port.stop();
}
