// The Dyna's "Modbus protocol" (Modbus-ASCII style, 8 data bits, even parity, 1 stop), as pure
// functions: frames, the LRC, typed requests and replies. No I/O. Source: application note
// SAN-220-4509; the reply formats it leaves out are assumptions A6..A9 in
// spectron/assumptions.h.
//
// Frame: ':' + address (2 hex, 1..250) + command (2 hex) + data (hex) + LRC (2 hex) + CR LF.
// The LRC is NOT the standard Modbus one: it is the two's complement of the 8-bit sum of the
// ASCII character codes between ':' and the LRC, so it depends on the letter case sent.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"
#include "spectron/protocol.h"

namespace tiltgate::spectron {

enum class AsciiCommand : std::uint8_t {
  reset = 0x65,             // reply ":AA65LRC"
  read_sensor = 0x66,       // reply: one signed word (A6)
  read_temperature = 0x67,  // reply: one signed word (A6)
  write_eeprom = 0x68,      // data: location (4 hex), value (4 hex); reply ":AA68LRC"
  read_eeprom = 0x69,       // data: location (4 hex); reply: one word (A6)
  revision = 0x6A,          // reply: one word, shown "HH.LL" (A7)
};
// "read sensor", or nullptr for a code the note does not list.
const char* ascii_command_name(std::uint8_t command);

// ':' + 2 + 2 + LRC 2 + CR LF.
inline constexpr std::size_t kMinFrameLength = 9;

struct AsciiFrame {
  std::uint8_t address = 0;
  std::uint8_t command = 0;
  std::vector<std::uint8_t> data;  // each byte is two hex digits on the wire

  bool operator==(const AsciiFrame&) const = default;
};

// Two's complement of the 8-bit sum of the character codes in `characters` (A8).
std::uint8_t lrc(std::string_view characters);

// ":" + uppercase hex + LRC over those characters + CR LF.
std::string encode_text(const AsciiFrame& frame);
std::vector<std::uint8_t> encode(const AsciiFrame& frame);

enum class AsciiDecodeError {
  no_start,    // does not begin with ':'
  no_end,      // does not end with CR LF
  too_short,   // fewer than address, command and LRC
  too_long,    // over kMaxFrameLength characters
  odd_digits,  // an odd number of hex digits
  not_hex,     // a character that is not a hex digit
  bad_lrc,     // the LRC does not match the characters received
};
const char* to_string(AsciiDecodeError error);

// `text` must be exactly one frame, ':' to LF. Hex is read in either case; the LRC is checked
// over the characters exactly as received.
Expected<AsciiFrame, AsciiDecodeError> decode(std::string_view text);

// Whether `reply` comes from the module `request` addressed and answers its command.
bool is_reply_to(const AsciiFrame& reply, const AsciiFrame& request);

// ---- Typed requests. The address must be 1..250; locations as eeprom::check_location. ----
using AsciiRequestResult = Expected<AsciiFrame, ArgumentError>;

AsciiRequestResult ascii_reset_request(int address);
AsciiRequestResult ascii_read_sensor_request(int address);
AsciiRequestResult ascii_read_temperature_request(int address);
AsciiRequestResult ascii_revision_request(int address);
AsciiRequestResult ascii_read_eeprom_request(int address, std::int64_t location);
AsciiRequestResult ascii_write_eeprom_request(int address, std::int64_t location,
                                              std::int64_t value);  // value 0..65535

// ---- Typed replies: each checks that `reply` answers `request` and has the expected data ----
Expected<Done, ReplyError> parse_ascii_ack(const AsciiFrame& reply,
                                           const AsciiFrame& request);  // reset, write
Expected<std::int16_t, ReplyError> parse_ascii_sensor_reply(const AsciiFrame& reply,
                                                            const AsciiFrame& request);
Expected<std::int16_t, ReplyError> parse_ascii_temperature_reply(const AsciiFrame& reply,
                                                                 const AsciiFrame& request);
Expected<std::uint16_t, ReplyError> parse_ascii_eeprom_reply(const AsciiFrame& reply,
                                                             const AsciiFrame& request);
Expected<std::string, ReplyError> parse_ascii_revision_reply(const AsciiFrame& reply,
                                                             const AsciiFrame& request);
// A7: 0x0107 -> "01.07".
std::string revision_text(std::uint16_t word);

// ---- The sensor side (the simulator) ----
AsciiFrame make_ascii_ack(std::uint8_t address, AsciiCommand command);
AsciiFrame make_ascii_word_reply(std::uint8_t address, AsciiCommand command, std::uint16_t word);
// The 16-bit word at data[2 * index], high byte first, or nullopt past the data.
std::optional<std::uint16_t> word_at(const AsciiFrame& frame, std::size_t index);

}  // namespace tiltgate::spectron
