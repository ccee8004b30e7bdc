// `tiltgate raw` on a Dyna bus. Modbus-ASCII: --function is the command code (0x65..0x6A, e.g.
// 0x69 read EEPROM with data 00 10), --data its data bytes, each sent as two hex digits; the
// address, LRC and CR LF are added. 9-bit: the protocol's commands are ASCII characters, so
// --function is the command character's code (0x41 'A' read sensor, 0x33 '3' read EEPROM) and
// --data the argument characters' codes (31 36 for location "16"); the address byte (sent with
// the 9th bit set) and CR LF are added. The replies are decoded by the codecs
// (spectron/ascii_codec.h, spectron/nine_bit_codec.h).
#pragma once

#include <memory>
#include <string>

#include "driver/family_commands.h"

namespace tiltgate::spectron {

inline constexpr std::string_view kRawFunctionHelp =
    "spectron-modbus: the command code (0x65..0x6A, e.g. 105 = 0x69 read EEPROM with data 00 10), "
    "--data its data bytes; spectron-9bit: the command character's code (65 = 'A' read sensor, "
    "51 = '3' read EEPROM), --data the argument characters' codes (31 36 for \"16\"); address, "
    "checksum and CR LF are added";

Expected<std::unique_ptr<RawExchange>, std::string> make_raw_exchange(const RawSetup& setup);

}  // namespace tiltgate::spectron
