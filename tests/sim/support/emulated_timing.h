// Timing a test cannot hold under an emulator. scripts/cross-arm64 runs the arm64 tests under
// qemu-user with TILTGATE_EMULATED=qemu set: there every instruction is translated, so a
// test that asserts what happens within a few milliseconds on the wire (two paced sends that
// overlap, a reply 50 ms late) sees the emulator's own delays instead. Such a test calls
// skip_if_emulated(why) first: under the emulator it stops with "skipped under emulation: WHY",
// which ctest counts as skipped (tests/CMakeLists.txt); anywhere else it returns. Every other
// test runs under qemu as it does here, so a new timing test that fails there is seen by CI
// (scripts/test --threads ends with scripts/package arm64), not left out by a list.
#pragma once

#include <doctest/doctest.h>

#include <cstdlib>
#include <string_view>

namespace tiltgate::test {

inline bool timing_is_emulated() {
  const char* emulator = std::getenv("TILTGATE_EMULATED");
  return emulator != nullptr && *emulator != '\0';
}

inline void skip_if_emulated(std::string_view why) {
  if (timing_is_emulated()) FAIL("skipped under emulation: " << why);
}

}  // namespace tiltgate::test
