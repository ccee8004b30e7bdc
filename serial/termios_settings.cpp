// The only file that sees the kernel's termios2: <asm/termbits.h> and glibc's <termios.h>
// both define struct termios and the flag names, so this file must not include <termios.h>
// (nor anything that does).
#include "serial/termios_settings.h"

#include <asm/termbits.h>
#include <linux/serial.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <optional>
#include <string>

namespace tiltgate {
namespace {

std::error_code last_error() { return std::error_code(errno, std::generic_category()); }

// What a port without termios2 answers: a kernel before 2.6.20 or a driver without it ENOTTY or
// EINVAL, qemu-user 7.2 ENOSYS (its "Unsupported ioctl: cmd=0x802c542a").
bool refuses_termios2(std::error_code error) {
  return error == std::errc::function_not_supported ||
         error == std::errc::inappropriate_io_control_operation ||
         error == std::errc::invalid_argument;
}

Expected<termios2, std::error_code> get(int fd, IoctlCall ioctl) {
  termios2 t{};
  if (ioctl(fd, TCGETS2, &t) != 0) return Unexpected(last_error());
  return t;
}

Expected<Done, std::error_code> set(int fd, const termios2& t, IoctlCall ioctl) {
  termios2 copy = t;
  if (ioctl(fd, TCSETS2, &copy) != 0) return Unexpected(last_error());
  return Done{};
}

// The older interface: the kernel's struct termios (no speed fields: the rate is a B-code in
// c_cflag's CBAUD bits, the input rate in CIBAUD, 0 there meaning "as the output").
Expected<termios, std::error_code> get_standard(int fd, IoctlCall ioctl) {
  termios t{};
  if (ioctl(fd, TCGETS, &t) != 0) return Unexpected(last_error());
  return t;
}

Expected<Done, std::error_code> set_standard(int fd, const termios& t, IoctlCall ioctl) {
  termios copy = t;  // what the call may change is not what the caller asked for
  if (ioctl(fd, TCSETS, &copy) != 0) return Unexpected(last_error());
  return Done{};
}

// The standard rates' codes, as <asm/termbits.h> defines them.
struct StandardRate {
  std::uint32_t baud;
  tcflag_t code;
};
constexpr StandardRate kStandardRates[] = {
    {50, B50},           {75, B75},           {110, B110},         {134, B134},
    {150, B150},         {200, B200},         {300, B300},         {600, B600},
    {1200, B1200},       {1800, B1800},       {2400, B2400},       {4800, B4800},
    {9600, B9600},       {19200, B19200},     {38400, B38400},     {57600, B57600},
    {115200, B115200},   {230400, B230400},   {460800, B460800},   {500000, B500000},
    {576000, B576000},   {921600, B921600},   {1000000, B1000000}, {1152000, B1152000},
    {1500000, B1500000}, {2000000, B2000000}, {2500000, B2500000}, {3000000, B3000000},
    {3500000, B3500000}, {4000000, B4000000}};

std::optional<tcflag_t> standard_code(std::uint32_t baud) {
  for (const StandardRate& rate : kStandardRates) {
    if (rate.baud == baud) return rate.code;
  }
  return std::nullopt;
}

std::uint32_t rate_of_code(tcflag_t code) {
  for (const StandardRate& rate : kStandardRates) {
    if (rate.code == code) return rate.baud;
  }
  return 0;  // B0, or a code we do not know
}

template <class Termios>
void set_parity_bits(Termios& t, Parity parity) {
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
template <class Termios>
void make_raw(Termios& t, Parity parity, int stop_bits) {
  t.c_iflag &= ~(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR | ICRNL | IXON | IXOFF |
                 IXANY | INPCK);
  t.c_iflag |= IGNPAR;
  t.c_oflag &= ~OPOST;
  t.c_lflag &= ~(ECHO | ECHONL | ICANON | ISIG | IEXTEN);
  t.c_cflag &= ~(CSIZE | CSTOPB | CRTSCTS);
  t.c_cflag |= CS8 | CLOCAL | CREAD;
  if (stop_bits == 2) t.c_cflag |= CSTOPB;
  set_parity_bits(t, parity);
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

template <class Termios>
TtySettings decode(const Termios& t) {
  TtySettings s;
  s.data_bits = data_bits_of(t.c_cflag);
  s.stop_bits = (t.c_cflag & CSTOPB) ? 2 : 1;
  s.parity_enabled = (t.c_cflag & PARENB) != 0;
  s.odd_parity = (t.c_cflag & PARODD) != 0;
  s.stick_parity = (t.c_cflag & CMSPAR) != 0;
  s.ignores_parity_errors = (t.c_iflag & IGNPAR) != 0;
  s.checks_input_parity = (t.c_iflag & INPCK) != 0;
  s.raw = !(t.c_lflag & (ECHO | ICANON | ISIG | IEXTEN)) && !(t.c_oflag & OPOST) &&
          !(t.c_iflag & (ISTRIP | INLCR | IGNCR | ICRNL));
  s.receiver_on = (t.c_cflag & CREAD) && (t.c_cflag & CLOCAL);
  s.flow_control = (t.c_cflag & CRTSCTS) || (t.c_iflag & (IXON | IXOFF));
  return s;
}

// Sets `wanted` through TCSETS and reads it back: an emulator may take the call and drop what
// it cannot translate (qemu 7.2 turns codes above B460800 into B0 and clears CMSPAR), which
// would otherwise leave a line at another rate or parity without a word.
Expected<Done, std::error_code> set_standard_checked(int fd, const termios& wanted,
                                                     IoctlCall ioctl) {
  if (auto applied = set_standard(fd, wanted, ioctl); !applied) return applied;
  auto kept = get_standard(fd, ioctl);
  if (!kept) return Unexpected(kept.error());
  if ((kept->c_cflag & CBAUD) != (wanted.c_cflag & CBAUD)) {
    return Unexpected(make_error_code(TermiosFallbackError::rate_not_kept));
  }
  if ((kept->c_cflag & CMSPAR) != (wanted.c_cflag & CMSPAR)) {
    return Unexpected(make_error_code(TermiosFallbackError::stick_parity_not_kept));
  }
  return Done{};
}

Expected<TermiosInterface, std::error_code> apply_standard(int fd, std::uint32_t baud,
                                                           Parity parity, int stop_bits,
                                                           IoctlCall ioctl) {
  const auto code = standard_code(baud);
  if (!code) return Unexpected(make_error_code(TermiosFallbackError::no_standard_code));
  auto t = get_standard(fd, ioctl);
  if (!t) return Unexpected(t.error());
  make_raw(*t, parity, stop_bits);
  t->c_cflag &= ~(CBAUD | CIBAUD);  // CIBAUD 0: input at the output's rate
  t->c_cflag |= *code;
  if (auto applied = set_standard_checked(fd, *t, ioctl); !applied) {
    return Unexpected(applied.error());
  }
  return TermiosInterface::standard_rates_only;
}

class TermiosFallbackCategory final : public std::error_category {
 public:
  const char* name() const noexcept override { return "termios fallback"; }
  std::string message(int value) const override {
    switch (TermiosFallbackError(value)) {
      case TermiosFallbackError::no_standard_code:
        return "this port does not take termios2, and the rate has no standard code";
      case TermiosFallbackError::rate_not_kept:
        return "this port does not take termios2, and it did not keep the rate's standard code";
      case TermiosFallbackError::stick_parity_not_kept:
        return "this port does not take termios2, and it dropped the mark/space parity bit";
    }
    return "unknown termios fallback error";
  }
};

}  // namespace

const std::error_category& termios_fallback_category() {
  static const TermiosFallbackCategory category;
  return category;
}

std::error_code make_error_code(TermiosFallbackError error) {
  return std::error_code(int(error), termios_fallback_category());
}

bool needs_termios2(std::error_code error) {
  return error.category() == termios_fallback_category();
}

std::string settings_error_text(std::error_code error, std::uint32_t baud) {
  if (!needs_termios2(error)) return error.message();
  const std::string port =
      "this port does not take termios2 (an old kernel, an emulator or its driver): ";
  const std::string rate = std::to_string(baud) + " baud";
  switch (TermiosFallbackError(error.value())) {
    case TermiosFallbackError::no_standard_code: return port + rate + " has no standard code";
    case TermiosFallbackError::rate_not_kept:
      return port + "it did not keep the standard code of " + rate;
    case TermiosFallbackError::stick_parity_not_kept:
      return port + "it dropped the mark/space parity bit (CMSPAR) that 9-bit framing needs";
  }
  return error.message();
}

int system_ioctl(int fd, unsigned long request, void* argument) {
  return ::ioctl(fd, request, argument);
}

int ioctl_without_termios2(int fd, unsigned long request, void* argument) {
  if (request == TCGETS2 || request == TCSETS2 || request == TCSETSW2 || request == TCSETSF2) {
    errno = ENOSYS;
    return -1;
  }
  return ::ioctl(fd, request, argument);
}

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

Expected<TermiosInterface, std::error_code> apply_raw_settings(int fd, std::uint32_t baud,
                                                               Parity parity, int stop_bits,
                                                               IoctlCall ioctl) {
  if (baud == 0) return Unexpected(std::make_error_code(std::errc::invalid_argument));
  auto t = get(fd, ioctl);
  if (!t && refuses_termios2(t.error())) return apply_standard(fd, baud, parity, stop_bits, ioctl);
  if (!t) return Unexpected(t.error());
  make_raw(*t, parity, stop_bits);
  set_baud(*t, baud);
  if (auto applied = set(fd, *t, ioctl); !applied) return Unexpected(applied.error());
  return TermiosInterface::termios2;
}

Expected<Done, std::error_code> apply_parity(int fd, Parity parity, IoctlCall ioctl) {
  auto t = get(fd, ioctl);
  if (!t && refuses_termios2(t.error())) {
    auto standard = get_standard(fd, ioctl);
    if (!standard) return Unexpected(standard.error());
    set_parity_bits(*standard, parity);
    return set_standard_checked(fd, *standard, ioctl);
  }
  if (!t) return Unexpected(t.error());
  set_parity_bits(*t, parity);
  return set(fd, *t, ioctl);
}

Expected<TtySettings, std::error_code> read_settings(int fd, IoctlCall ioctl) {
  auto t = get(fd, ioctl);
  if (!t && refuses_termios2(t.error())) {
    auto standard = get_standard(fd, ioctl);
    if (!standard) return Unexpected(standard.error());
    TtySettings s = decode(*standard);
    s.output_baud = rate_of_code(standard->c_cflag & CBAUD);
    const tcflag_t input_code = (standard->c_cflag & CIBAUD) >> IBSHIFT;
    s.input_baud = input_code == 0 ? s.output_baud : rate_of_code(input_code);
    return s;
  }
  if (!t) return Unexpected(t.error());
  TtySettings s = decode(*t);
  s.output_baud = t->c_ospeed;
  s.input_baud = t->c_ispeed;
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

Expected<UartCounts, std::error_code> uart_counts(int fd) {
  serial_icounter_struct counts{};
  if (::ioctl(fd, TIOCGICOUNT, &counts) != 0) return Unexpected(last_error());
  const auto count = [](int value) { return std::uint64_t(std::uint32_t(value)); };
  return UartCounts{count(counts.overrun) + count(counts.buf_overrun),
                    count(counts.frame) + count(counts.parity)};
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
