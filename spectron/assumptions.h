// Every choice made where the Dyna application note (SAN-220-4509) is silent, in one place so
// the README can cite it. Each constant below is used by the codecs; change it here only.
//
// 9-bit addressing ("1st Protocol")
//  A1. Numbers are decimal ASCII text. The note's examples read as decimal: "34" (an even
//      location), "2501", "Unit Returns 1001".
//  A2. Read EEPROM is "3" + the location in decimal + CR LF ("3" and "E" share the location
//      format; the note gives no argument for "3"). Example: location 22 -> "322\r\n".
//  A3. Write EEPROM is "E" + location + one delimiter + value + CR LF, all decimal; the gateway
//      sends ',' (the note's example, ASCII 44) unless told otherwise: "E34,2501\r\n".
//  A4. Replies to "3", "A" and "C" are one decimal number (optional sign, leading zeros and
//      surrounding spaces tolerated) + CR LF; "F" is free text + CR LF; "0" (reset) and "E"
//      (write) return a line whose content is not looked at ("returns with carriage return and
//      line feed"): an empty line, or any text, is the acknowledgement.
//  A5. A reply line holds printable ASCII only; other bytes (line noise, 0x00/0xFF from the
//      bus turning round) are dropped one by one, and a line longer than kMaxLineLength is
//      garbage: dropped up to its CR LF.
//
// Modbus-ASCII style ("Modbus protocol")
//  A6. Replies to 0x66 (read sensor), 0x67 (read temperature), 0x69 (read EEPROM) and 0x6A
//      (revision) are ':' + address + command + one 16-bit word as 4 hex digits + LRC + CR LF.
//      Sensor counts and temperature are signed (two's complement); the EEPROM word is
//      unsigned. Example: module 1 reads 1001 counts -> ":0166" "03E9" + LRC.
//  A7. The revision word is shown as "HH.LL": its high and low bytes as 2 hex digits each, as
//      they appear on the wire (0x0107 -> "01.07").
//  A8. The LRC covers exactly the characters between ':' and the LRC as they were sent, so the
//      letter case of hex digits matters (the note's ":01680016000F74" only checks if the F was
//      sent as 'f'); hex is read in either case, and the encoder sends uppercase.
//  A9. A frame longer than kMaxFrameLength characters is garbage (the longest documented frame,
//      a write, has 17).
//
// EEPROM ("Memory Map")
//  A10. Locations are even: 2..22 as listed, and 100..280 ("reserved"). Nothing else is read
//       or written. Writable through the gateway: 6, 10, 20 (offsets: a raw 16-bit word,
//       0..65535), 16 (module address: 0..255 on the 9-bit bus, 1..250 on Modbus-ASCII) and 22
//       (baud: only the five listed codes); the reserved 100..280 only when the sensor's
//       eeprom_reserved_writes says so (the note's own example writes 355 to location 100).
#pragma once

#include <cstddef>

namespace tiltgate::spectron {

inline constexpr std::size_t kMaxLineLength = 64;   // A5: a 9-bit reply line, CR LF excluded
inline constexpr std::size_t kMaxFrameLength = 64;  // A9: a Modbus-ASCII frame, ':' to LF
inline constexpr char kDefaultDelimiter = ',';      // A3
inline constexpr std::size_t kReplyWordDigits = 4;  // A6: one 16-bit word, 4 hex digits

}  // namespace tiltgate::spectron
