// The only file that sees the kernel's termios2: <asm/termbits.h> and glibc's <termios.h>
// both define struct termios and the flag names, so this file must not include <termios.h>
// (nor anything that does).
#include "serial/termios_settings.h"

#include <asm/termbits.h>
#include <linux/serial.h>
#include <sys/ioctl.h>

#include <cerrno>

namespace tiltgate {
namespace {

std::error_code last_error() { return std::error_code(errno, std::generic_category()); }

Expected<termios2, std::error_code> get(int fd) {
  termios2 t{};
  if (::ioctl(fd, TCGETS2, &t) != 0) return Unexpected(last_error());
  return t;
}

Expected<Done, std::error_code> set(int fd, const termios2& t) {
  if (::ioctl(fd, TCSETS2, &t) != 0) return Unexpected(last_error());
  return Done{};
}

void set_parity_bits(termios2& t, Parity parity) {
  t.c_cflag &= ~(PARENB | PARODD | CMSPAR);
  switch (parity) {
    case Parity::none: break;
    case Parity::even: t.c_cflag |= PARENB; break;
    case Parity::odd: t.c_cflag |= PARENB | PARODD; break;
    case Parity::mark: t.c_cflag |= PARENB | PARODD | CMSPAR; break;
    case Parity::space: t.c_cflag |= PARENB | CMSPAR; break;
  }
}

// What cfmakeraw() does, plus no flow control, receiver on, modem lines ignored, and input
// parity ignored.
void make_raw(termios2& t) {
  t.c_iflag &= ~(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR | ICRNL | IXON | IXOFF |
                 IXANY | INPCK);
  t.c_iflag |= IGNPAR;
  t.c_oflag &= ~OPOST;
  t.c_lflag &= ~(ECHO | ECHONL | ICANON | ISIG | IEXTEN);
  t.c_cflag &= ~(CSIZE | CSTOPB | CRTSCTS);
  t.c_cflag |= CS8 | CLOCAL | CREAD;
  // Reads are non-blocking and driven by Asio, so these only matter to a blocking reader.
  t.c_cc[VMIN] = 1;
  t.c_cc[VTIME] = 0;
}

// BOTHER takes the rate from c_ospeed/c_ispeed as a number, standard or not.
void set_baud(termios2& t, std::uint32_t baud) {
  t.c_cflag &= ~(CBAUD | (CBAUD << IBSHIFT));
  t.c_cflag |= BOTHER | (BOTHER << IBSHIFT);
  t.c_ospeed = baud;
  t.c_ispeed = baud;
}

int data_bits_of(tcflag_t cflag) {
  switch (cflag & CSIZE) {
    case CS5: return 5;
    case CS6: return 6;
    case CS7: return 7;
    default: return 8;
  }
}

}  // namespace

const char* to_string(Parity parity) {
  switch (parity) {
    case Parity::none: return "none";
    case Parity::even: return "even";
    case Parity::odd: return "odd";
    case Parity::mark: return "mark";
    case Parity::space: return "space";
  }
  return "unknown";
}

Parity TtySettings::parity() const {
  if (!parity_enabled) return Parity::none;
  if (stick_parity) return odd_parity ? Parity::mark : Parity::space;
  return odd_parity ? Parity::odd : Parity::even;
}

Expected<Done, std::error_code> apply_raw_settings(int fd, std::uint32_t baud, Parity parity,
                                                   int stop_bits) {
  if (baud == 0) return Unexpected(std::make_error_code(std::errc::invalid_argument));
  auto t = get(fd);
  if (!t) return Unexpected(t.error());
  make_raw(*t);
  set_baud(*t, baud);
  set_parity_bits(*t, parity);
  if (stop_bits == 2) t->c_cflag |= CSTOPB;  // make_raw cleared it
  return set(fd, *t);
}

Expected<Done, std::error_code> apply_parity(int fd, Parity parity) {
  auto t = get(fd);
  if (!t) return Unexpected(t.error());
  set_parity_bits(*t, parity);
  return set(fd, *t);
}

Expected<TtySettings, std::error_code> read_settings(int fd) {
  auto t = get(fd);
  if (!t) return Unexpected(t.error());
  TtySettings s;
  s.output_baud = t->c_ospeed;
  s.input_baud = t->c_ispeed;
  s.data_bits = data_bits_of(t->c_cflag);
  s.stop_bits = (t->c_cflag & CSTOPB) ? 2 : 1;
  s.parity_enabled = (t->c_cflag & PARENB) != 0;
  s.odd_parity = (t->c_cflag & PARODD) != 0;
  s.stick_parity = (t->c_cflag & CMSPAR) != 0;
  s.ignores_parity_errors = (t->c_iflag & IGNPAR) != 0;
  s.checks_input_parity = (t->c_iflag & INPCK) != 0;
  s.raw = !(t->c_lflag & (ECHO | ICANON | ISIG | IEXTEN)) && !(t->c_oflag & OPOST) &&
          !(t->c_iflag & (ISTRIP | INLCR | IGNCR | ICRNL));
  s.receiver_on = (t->c_cflag & CREAD) && (t->c_cflag & CLOCAL);
  s.flow_control = (t->c_cflag & CRTSCTS) || (t->c_iflag & (IXON | IXOFF));
  return s;
}

Expected<Done, std::error_code> enable_kernel_rs485(int fd) {
  serial_rs485 rs485{};
  rs485.flags = SER_RS485_ENABLED | SER_RS485_RTS_ON_SEND;
  if (::ioctl(fd, TIOCSRS485, &rs485) != 0) return Unexpected(last_error());
  return Done{};
}

Expected<Done, std::error_code> wait_until_sent(int fd) {
  // TCSBRK with a non-zero argument is tcdrain() (glibc implements it the same way).
  if (::ioctl(fd, TCSBRK, 1) != 0) return Unexpected(last_error());
  return Done{};
}

Expected<Done, std::error_code> discard_input(int fd) {
  if (::ioctl(fd, TCFLSH, TCIFLUSH) != 0) return Unexpected(last_error());
  return Done{};
}

int bits_per_byte(Parity parity, int stop_bits) {
  return 9 + (parity == Parity::none ? 0 : 1) + stop_bits;
}

std::chrono::microseconds wire_time(std::size_t bytes, std::uint32_t baud, Parity parity,
                                    int stop_bits) {
  if (baud == 0) return std::chrono::microseconds{0};
  const std::uint64_t bits = std::uint64_t(bytes) * std::uint64_t(bits_per_byte(parity, stop_bits));
  return std::chrono::microseconds{(bits * 1'000'000 + baud - 1) / baud};
}

}  // namespace tiltgate
