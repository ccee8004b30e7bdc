// The Dyna's "1st Protocol", 9-bit addressing, as pure functions: requests, the sensor side's
// reading of a request, and replies. No I/O. Source: application note SAN-220-4509; every
// choice where it is silent is in spectron/assumptions.h (A1..A5).
//
// On the wire a request is one address byte sent with the 9th bit set (mark parity on a PC
// UART), then the body with the 9th bit clear (space parity): one ASCII command, its
// arguments, CR LF. Replies are text ending in CR LF and carry no address: only the addressed
// module answers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"
#include "spectron/assumptions.h"
#include "spectron/protocol.h"

namespace tiltgate::spectron {

// "Commands", sent as one ASCII character.
enum class NineBitCommand : char {
  reset = '0',
  read_eeprom = '3',
  read_sensor = 'A',
  read_temperature = 'C',
  write_eeprom = 'E',
  firmware = 'F',
};
const char* command_name(NineBitCommand command);  // "read sensor"
std::optional<NineBitCommand> nine_bit_command(char c);

// "delimits address and data can be a space or "," or ":" or tab".
bool is_nine_bit_delimiter(char c);

inline constexpr std::size_t kNineBitAddressBytes = 1;

struct NineBitRequest {
  std::uint8_t address = 0;        // "bAddress can be between 0 and 255"
  std::vector<std::uint8_t> body;  // command, arguments, CR LF

  bool operator==(const NineBitRequest&) const = default;
};
// The address byte followed by the body: a LineRequest's bytes, with address_bytes =
// kNineBitAddressBytes so the line sends the first with mark parity and the rest with space.
std::vector<std::uint8_t> wire_bytes(const NineBitRequest& request);

using NineBitRequestResult = Expected<NineBitRequest, ArgumentError>;

NineBitRequest nine_bit_reset_request(std::uint8_t address);             // "0\r\n"
NineBitRequest nine_bit_read_sensor_request(std::uint8_t address);       // "A\r\n"
NineBitRequest nine_bit_read_temperature_request(std::uint8_t address);  // "C\r\n"
NineBitRequest nine_bit_firmware_request(std::uint8_t address);          // "F\r\n"
// "3" + location (A2). The location must be in the memory map (eeprom::check_location).
NineBitRequestResult nine_bit_read_eeprom_request(std::uint8_t address, std::int64_t location);
// "E" + location + delimiter + value (A3); value 0..65535, delimiter ' ', ',', ':' or tab.
NineBitRequestResult nine_bit_write_eeprom_request(std::uint8_t address, std::int64_t location,
                                                   std::int64_t value,
                                                   char delimiter = kDefaultDelimiter);

// ---- The sensor side (the simulator): what a request body asks for ----
struct NineBitCommandLine {
  NineBitCommand command = NineBitCommand::read_sensor;
  std::optional<std::uint16_t> location;  // read and write EEPROM
  std::optional<std::uint16_t> value;     // write EEPROM
};
// `body` without its CR LF. Numbers are 1..5 decimal digits up to 65535; any location parses
// (the sensor decides what it accepts). The error says what is wrong.
Expected<NineBitCommandLine, std::string> parse_nine_bit_body(std::string_view body);
// A reply line: `text` + CR LF.
std::vector<std::uint8_t> nine_bit_reply_line(std::string_view text);

// ---- Replies (A4). `line` is one line as NineBitLineParser returns it, without CR LF ----
struct NineBitNumber {
  std::int32_t value = 0;
  std::string text;  // the line as received, for diagnostics
};
// One decimal number: optional sign, leading zeros and spaces/tabs around it tolerated.
Expected<NineBitNumber, ReplyError> parse_nine_bit_number(std::string_view line);
// The firmware revision text, spaces trimmed; an empty line is bad_text.
Expected<std::string, ReplyError> parse_nine_bit_firmware(std::string_view line);

struct LineParserCounters {
  std::uint64_t lines_ok = 0;
  std::uint64_t overlong_lines = 0;  // lines over kMaxLineLength, dropped up to their CR LF
  std::uint64_t bytes_dropped = 0;   // non-printable bytes, lone CRs, overlong lines, reset()
};

// Splits a byte stream fed in arbitrary chunks into reply lines (A5): a line ends at CR LF;
// bytes that are not printable ASCII (or tab) are dropped one by one; a line longer than
// kMaxLineLength is dropped up to its CR LF. The buffer never holds more than kMaxLineLength.
class NineBitLineParser {
 public:
  // Consumes all of `bytes`; returns how many lines are waiting in next().
  std::size_t feed(std::span<const std::uint8_t> bytes);
  // The oldest line not yet taken, without its CR LF.
  std::optional<std::string> next();
  // Drops the partial line and waiting lines: the start of a new exchange.
  void reset();

  std::size_t buffered() const { return line_.size(); }
  const LineParserCounters& counters() const { return counters_; }

 private:
  void take(std::uint8_t byte);
  void end_line();

  std::string line_;
  bool after_cr_ = false;
  bool overlong_ = false;
  std::deque<std::string> ready_;
  LineParserCounters counters_;
};

}  // namespace tiltgate::spectron
