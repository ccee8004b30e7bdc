// Modbus RTU character framing and the silences that delimit frames (Modbus over Serial Line
// V1.02, 2.5.1 and 2.5.1.1): a character is a start bit, 8 data bits, a parity bit (even by
// default) and one stop bit, or, without parity, two stop bits, so 11 bits either way. Frames
// are separated by at least 3.5 character times of silence (t3.5); inside a frame no gap may
// exceed 1.5 character times (t1.5). Above 19200 baud the spec fixes them at 1750 us and
// 750 us, because recomputing them per baud would load the slave's CPU for no gain.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>

#include "mapping/point_types.h"

namespace tiltgate::modbus_rtu {

enum class Parity : std::uint8_t { even, odd, none };

// "even", "odd", "none": the names a [[bus]] parity key takes.
std::span<const Named<Parity>> parity_names();

// Serial Line 2.5.1: two stop bits without parity, so a character stays 11 bits long.
int default_stop_bits(Parity parity);

// Start bit + 8 data bits + parity bit (if any) + stop bits: 11 for 8E1, 8O1 and 8N2, 10 for
// 8N1.
unsigned bits_per_character(Parity parity, int stop_bits);

struct RtuTiming {
  std::chrono::microseconds character;   // one character on the wire
  std::chrono::microseconds frame_gap;   // t3.5: the silence that ends a frame
  std::chrono::microseconds char_gap;    // t1.5: the longest gap allowed inside a frame
};

// Times rounded up to whole microseconds (waiting a fraction longer is always safe); baud > 0.
RtuTiming rtu_timing(std::uint32_t baud, unsigned bits_per_char);

}  // namespace tiltgate::modbus_rtu
