// Terminal settings of a serial port, applied and read back through the Linux termios2 ioctls
// (TCSETS2/TCGETS2 with BOTHER), so any baud rate works, 125000 and 62500 included.
//
// A port that refuses termios2 (ENOSYS, ENOTTY or EINVAL from TCGETS2: an old kernel, an
// emulator such as qemu-user 7.2, an odd USB driver) is set through the older TCGETS/TCSETS
// instead, which take only the standard rates' codes (B50 to B4000000). There a rate without a
// code, or a setting the port does not keep, is an error that says so (settings_error_text).
//
// This header includes neither <termios.h> nor <asm/termbits.h>: the two define the same names
// differently, so only termios_settings.cpp sees the kernel's, and callers see the plain types
// below. Every function takes an open tty descriptor and returns the errno as a value.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <string>
#include <system_error>
#include <type_traits>

#include "driver/expected.h"
#include "driver/framing.h"

namespace tiltgate {

// mark/space are "stick" parity (CMSPAR): the parity bit is a constant 1 or 0, which is how a
// PC UART sends the ninth bit of a 9-bit bus (docs/protocols.md, "9-bit framing on a PC UART").
enum class Parity { none, even, odd, mark, space };

const char* to_string(Parity parity);

// The parity of every byte of `framing` but a 9-bit bus's address bytes, which switch to mark.
constexpr Parity idle_parity(Framing framing) {
  switch (framing) {
    case Framing::eight_none_one: return Parity::none;
    case Framing::eight_even_one: return Parity::even;
    case Framing::eight_odd_one: return Parity::odd;
    case Framing::eight_none_two: return Parity::none;
    case Framing::nine_bit: return Parity::space;
  }
  return Parity::none;
}

// What a tty is set to, decoded from its termios2.
struct TtySettings {
  std::uint32_t output_baud = 0;
  std::uint32_t input_baud = 0;
  int data_bits = 0;
  int stop_bits = 0;
  // The parity bits are kept apart because a pseudo-terminal keeps PARODD and CMSPAR but
  // always clears PARENB (Linux pty_set_termios), so tests on a pty can only see those two.
  bool parity_enabled = false;  // PARENB
  bool odd_parity = false;      // PARODD (with CMSPAR: mark)
  bool stick_parity = false;    // CMSPAR (mark or space)
  bool ignores_parity_errors = false;  // IGNPAR
  bool checks_input_parity = false;    // INPCK
  bool raw = false;           // no line editing, echo, signals, CR/LF mapping, output processing
  bool receiver_on = false;   // CREAD and CLOCAL (no modem control lines needed)
  bool flow_control = false;  // CRTSCTS, IXON or IXOFF

  // The parity as configured (what the UART sends), decoded from the three bits above.
  Parity parity() const;
};

// How settings reached the port: termios2 (any rate), or, on a port that refuses termios2, the
// older TCSETS with a standard rate's code. The caller logs the second once per port.
enum class TermiosInterface { termios2, standard_rates_only };

// Why a port that refuses termios2 could not be set through TCSETS. Each is a std::error_code of
// termios_fallback_category(); settings_error_text() names the rate.
enum class TermiosFallbackError {
  no_standard_code = 1,  // the rate has no B-code
  rate_not_kept,         // the port read back another code (qemu 7.2 drops those above B460800)
  stick_parity_not_kept  // the port dropped CMSPAR (qemu 7.2 does), which 9-bit framing needs
};
const std::error_category& termios_fallback_category();
std::error_code make_error_code(TermiosFallbackError error);

// True for the errors above: the settings need termios2, which this port does not take.
bool needs_termios2(std::error_code error);

// `error` as a log line's reason, naming `baud` where that is the trouble, e.g. "this port does
// not take termios2 (an old kernel, an emulator or its driver): 125000 baud has no standard code".
std::string settings_error_text(std::error_code error, std::uint32_t baud);

// The ioctl(2) the settings functions call: system_ioctl, or a stand-in (tests).
using IoctlCall = int (*)(int fd, unsigned long request, void* argument);
int system_ioctl(int fd, unsigned long request, void* argument);
// What a port without termios2 does: TCGETS2 and the TCSETS2 family fail with ENOSYS, as under
// qemu-user 7.2; every other request goes to ioctl(2). Lets a test on a pseudo-terminal take the
// fallback on any machine.
int ioctl_without_termios2(int fd, unsigned long request, void* argument);

// Raw 8-bit mode at `baud` with the given parity and stop bits (1 or 2); receiver on, no modem
// control, no flow control. Input parity is never checked (IGNPAR, no INPCK): a reply's own
// checksum decides whether it is good, and on a 9-bit bus the received ninth bit means nothing.
// EINVAL for baud 0 (which would mean "hang up").
Expected<TermiosInterface, std::error_code> apply_raw_settings(int fd, std::uint32_t baud,
                                                               Parity parity, int stop_bits = 1,
                                                               IoctlCall ioctl = system_ioctl);

// Changes only the parity, at once (TCSETS2, not the draining variant): the caller waits for
// earlier bytes to leave first (wait_until_sent) when that matters.
Expected<Done, std::error_code> apply_parity(int fd, Parity parity,
                                             IoctlCall ioctl = system_ioctl);

Expected<TtySettings, std::error_code> read_settings(int fd, IoctlCall ioctl = system_ioctl);

// Kernel-driven RS485 direction control (TIOCSRS485: SER_RS485_ENABLED | RTS_ON_SEND), for
// on-board UARTs whose driver supports it. Fails with ENOTTY on USB adapters that switch
// direction themselves and on pseudo-terminals.
Expected<Done, std::error_code> enable_kernel_rs485(int fd);

// tcdrain(): BLOCKS until every byte written so far has left the UART. Bounded by the bytes
// still queued (a few byte-times when used after a short write) since flow control is off.
Expected<Done, std::error_code> wait_until_sent(int fd);

// tcflush(TCIFLUSH): drops whatever has been received and not read yet.
Expected<Done, std::error_code> discard_input(int fd);
// What the UART counted wrong since the port was opened (TIOCGICOUNT): characters lost to
// overruns (its own and its driver's buffer's), and characters received with a framing or a
// parity error. Pseudo-terminals and many USB adapters' drivers cannot say (ENOTTY, EINVAL).
struct UartCounts {
  std::uint64_t overruns = 0;
  std::uint64_t framing_errors = 0;  // framing and parity errors together
};
Expected<UartCounts, std::error_code> uart_counts(int fd);

// Bits on the wire per byte: start + 8 data + (parity) + stop bits.
int bits_per_byte(Parity parity, int stop_bits = 1);

// How long `bytes` bytes take to send at `baud`, rounded up to the microsecond.
std::chrono::microseconds wire_time(std::size_t bytes, std::uint32_t baud, Parity parity,
                                    int stop_bits = 1);

}  // namespace tiltgate

template <>
struct std::is_error_code_enum<tiltgate::TermiosFallbackError> : std::true_type {};
