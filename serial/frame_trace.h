// What `--log-level trace` shows of a Line's traffic: one line per request written and per
// frame (or run of rejected bytes) received, in hex, with its direction, its time and what was
// made of it. Pure formatting; SerialLine calls these only when trace logging is on and puts the
// bus name in front:
//
//   line1 -> 01 03 00 00 00 0A C5 CD
//   line1 -> [05] 41 0D 0A                  9-bit: the address bytes (9th bit set) in brackets
//   line1 <- 01 03 14 ... 3B 8E (12 ms, CRC ok)
//   line1 <- 7F 00 (skipped)                bytes before the reply that were not part of it
//   line1 <- 01 03 14 ... (no reply within 50 ms: bad CRC)
//   line1 no reply within 50 ms             a time-out with nothing received
//   line1 <- 01 03 14 ... (discarded: late, 480 ms after the request)
//
// Times count from the end of the request on the wire (driver/line.h, LineTiming).
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "driver/line.h"

namespace tiltgate {

// "-> 01 03 ..."; the first `address_bytes` bytes in brackets (9-bit buses only).
std::string traced_request(std::span<const std::uint8_t> bytes, std::size_t address_bytes);

// An accepted attempt's bytes in their parts: those before the reply (skipped, or the framer's
// rejected verdict), the reply with its verdict, and those after it; each part a frame of the
// capture (driver/captured_frame.h) and a line of the trace. All of `received` as the reply when
// the framer gave no report or the reply is not found whole among the bytes read (a noise byte
// inside it was dropped).
struct ReceivedPart {
  std::span<const std::uint8_t> bytes;
  std::string verdict;
  bool is_reply = false;
};
std::vector<ReceivedPart> reply_parts(std::span<const std::uint8_t> received,
                                      const FramerReport& report);

// The lines for an attempt the framer accepted: the bytes before the reply (skipped, or the
// framer's rejected verdict), the reply with its delay and verdict, and bytes after it.
// `received` is everything read in the attempt (an echo of the request excluded).
std::vector<std::string> traced_reply(std::span<const std::uint8_t> received,
                                      const FramerReport& report,
                                      std::chrono::milliseconds delay);

// A time-out, with the bytes received so far and what the framer made of them.
std::string traced_timeout(std::span<const std::uint8_t> received, const FramerReport& report,
                           std::chrono::milliseconds timeout);

// Bytes that came after a time-out, discarded by the late-reply guard.
std::string traced_late(std::span<const std::uint8_t> discarded,
                        std::chrono::milliseconds after_request);

}  // namespace tiltgate
