// Terminal settings of a serial port, applied and read back through the Linux termios2 ioctls
// (TCSETS2/TCGETS2 with BOTHER), so any baud rate works, 125000 and 62500 included.
//
// This header includes neither <termios.h> nor <asm/termbits.h>: the two define the same names
// differently, so only termios_settings.cpp sees the kernel's, and callers see the plain types
// below. Every function takes an open tty descriptor and returns the errno as a value.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <system_error>

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

// Raw 8-bit mode at `baud` with the given parity and stop bits (1 or 2); receiver on, no modem
// control, no flow control. Input parity is never checked (IGNPAR, no INPCK): a reply's own
// checksum decides whether it is good, and on a 9-bit bus the received ninth bit means nothing.
// EINVAL for baud 0 (which would mean "hang up").
Expected<Done, std::error_code> apply_raw_settings(int fd, std::uint32_t baud, Parity parity,
                                                   int stop_bits = 1);

// Changes only the parity, at once (TCSETS2, not the draining variant): the caller waits for
// earlier bytes to leave first (wait_until_sent) when that matters.
Expected<Done, std::error_code> apply_parity(int fd, Parity parity);

Expected<TtySettings, std::error_code> read_settings(int fd);

// Kernel-driven RS485 direction control (TIOCSRS485: SER_RS485_ENABLED | RTS_ON_SEND), for
// on-board UARTs whose driver supports it. Fails with ENOTTY on USB adapters that switch
// direction themselves and on pseudo-terminals.
Expected<Done, std::error_code> enable_kernel_rs485(int fd);

// tcdrain(): BLOCKS until every byte written so far has left the UART. Bounded by the bytes
// still queued (a few byte-times when used after a short write) since flow control is off.
Expected<Done, std::error_code> wait_until_sent(int fd);

// tcflush(TCIFLUSH): drops whatever has been received and not read yet.
Expected<Done, std::error_code> discard_input(int fd);

// Bits on the wire per byte: start + 8 data + (parity) + stop bits.
int bits_per_byte(Parity parity, int stop_bits = 1);

// How long `bytes` bytes take to send at `baud`, rounded up to the microsecond.
std::chrono::microseconds wire_time(std::size_t bytes, std::uint32_t baud, Parity parity,
                                    int stop_bits = 1);

}  // namespace tiltgate
