// Serial settings a test needs that this machine's ports may not take. On a port that refuses
// termios2 (under qemu-user 7.2, which runs scripts/cross-arm64's tests) a line is set through
// TCSETS: a rate with no standard code, or mark/space parity that the emulator drops, cannot be
// set there (serial/termios_settings.h). A test that needs such a line calls
// skip_unless_settable() before it opens one: when a pseudo-terminal refuses the settings for that
// reason, the test stops with "skipped without termios2: WHY", which ctest counts as skipped
// (tests/CMakeLists.txt); anywhere else it returns and the test goes on. Header-only, so the unit
// tests' benches on a simulated bus use it too.
#pragma once

#include <doctest/doctest.h>

#include <cstdint>
#include <system_error>

#include "serial/pseudo_terminal.h"
#include "serial/serial_line.h"
#include "serial/termios_settings.h"

namespace tiltgate::test {

// Stops the test, saying why, when a port without termios2 refused the settings.
inline void skip_if_termios2_missing(std::error_code error, std::uint32_t baud) {
  if (!needs_termios2(error)) return;
  FAIL("skipped without termios2: " << settings_error_text(error, baud));
}

inline void skip_unless_settable(std::uint32_t baud, Parity parity = Parity::none,
                                 int stop_bits = 1) {
  auto pty = PseudoTerminal::open();
  REQUIRE_MESSAGE(pty.has_value(), (pty ? "" : pty.error()));
  if (auto applied = apply_raw_settings(pty->slave_fd(), baud, parity, stop_bits); !applied) {
    skip_if_termios2_missing(applied.error(), baud);
  }
  // A 9-bit line sends its address bytes with mark parity, its data with space.
  if (parity != Parity::space) return;
  if (auto mark = apply_parity(pty->slave_fd(), Parity::mark); !mark) {
    skip_if_termios2_missing(mark.error(), baud);
  }
}

// The line's baud and framing.
inline void skip_unless_settable(const SerialLineOptions& options) {
  skip_unless_settable(options.baud, idle_parity(options.framing), stop_bits_of(options.framing));
}

}  // namespace tiltgate::test
