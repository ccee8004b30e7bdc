#include "spectron/nine_bit_codec.h"

#include <charconv>
#include <limits>

#include "spectron/eeprom_map.h"

namespace tiltgate::spectron {
namespace {

constexpr std::string_view kCrLf = "\r\n";
constexpr std::size_t kMaxNumberDigits = 5;  // 65535

bool is_space(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

// Printable ASCII and tab: what a reply line may hold (A5).
bool is_line_character(std::uint8_t byte) { return (byte >= 0x20 && byte <= 0x7E) || byte == '\t'; }

NineBitRequest request(std::uint8_t address, std::string_view body) {
  NineBitRequest out{address, std::vector<std::uint8_t>(body.begin(), body.end())};
  out.body.insert(out.body.end(), kCrLf.begin(), kCrLf.end());
  return out;
}

std::string command_text(NineBitCommand command) {
  return std::string(1, static_cast<char>(command));
}

// 1..5 decimal digits at the front of `text`, up to 65535; consumed from `text`.
std::optional<std::uint16_t> take_number(std::string_view& text) {
  std::size_t digits = 0;
  while (digits < text.size() && text[digits] >= '0' && text[digits] <= '9') ++digits;
  if (digits == 0 || digits > kMaxNumberDigits) return std::nullopt;
  std::uint32_t value = 0;
  std::from_chars(text.data(), text.data() + digits, value);
  if (value > eeprom::kMaxValue) return std::nullopt;
  text.remove_prefix(digits);
  return static_cast<std::uint16_t>(value);
}

// For messages: the text in quotes, with anything not printable shown as \xHH.
std::string quoted(std::string_view text) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out = "\"";
  for (char c : text) {
    const auto byte = static_cast<std::uint8_t>(c);
    if (byte >= 0x20 && byte <= 0x7E) {
      out += c;
    } else {
      out += "\\x";
      out += kHex[byte >> 4];
      out += kHex[byte & 0x0F];
    }
  }
  return out + "\"";
}

}  // namespace

const char* command_name(NineBitCommand command) {
  switch (command) {
    case NineBitCommand::reset: return "reset";
    case NineBitCommand::read_eeprom: return "read EEPROM";
    case NineBitCommand::read_sensor: return "read sensor";
    case NineBitCommand::read_temperature: return "read temperature";
    case NineBitCommand::write_eeprom: return "write EEPROM";
    case NineBitCommand::firmware: return "firmware revision";
  }
  return "unknown command";
}

std::optional<NineBitCommand> nine_bit_command(char c) {
  switch (c) {
    case '0':
    case '3':
    case 'A':
    case 'C':
    case 'E':
    case 'F': return static_cast<NineBitCommand>(c);
    default: return std::nullopt;
  }
}

bool is_nine_bit_delimiter(char c) { return c == ' ' || c == ',' || c == ':' || c == '\t'; }

std::vector<std::uint8_t> wire_bytes(const NineBitRequest& request) {
  std::vector<std::uint8_t> bytes;
  bytes.reserve(1 + request.body.size());
  bytes.push_back(request.address);
  bytes.insert(bytes.end(), request.body.begin(), request.body.end());
  return bytes;
}

NineBitRequest nine_bit_reset_request(std::uint8_t address) {
  return request(address, command_text(NineBitCommand::reset));
}

NineBitRequest nine_bit_read_sensor_request(std::uint8_t address) {
  return request(address, command_text(NineBitCommand::read_sensor));
}

NineBitRequest nine_bit_read_temperature_request(std::uint8_t address) {
  return request(address, command_text(NineBitCommand::read_temperature));
}

NineBitRequest nine_bit_firmware_request(std::uint8_t address) {
  return request(address, command_text(NineBitCommand::firmware));
}

NineBitRequestResult nine_bit_read_eeprom_request(std::uint8_t address, std::int64_t location) {
  if (auto known = eeprom::check_location(location); !known) {
    return Unexpected(ArgumentError{known.error()});
  }
  return request(address, command_text(NineBitCommand::read_eeprom) + std::to_string(location));
}

NineBitRequestResult nine_bit_write_eeprom_request(std::uint8_t address, std::int64_t location,
                                                   std::int64_t value, char delimiter) {
  if (auto known = eeprom::check_location(location); !known) {
    return Unexpected(ArgumentError{known.error()});
  }
  if (value < 0 || value > eeprom::kMaxValue) {
    return Unexpected(ArgumentError{"EEPROM value " + std::to_string(value) +
                                    " is out of range 0..65535"});
  }
  if (!is_nine_bit_delimiter(delimiter)) {
    return Unexpected(ArgumentError{"the delimiter must be a space, ',', ':' or a tab"});
  }
  return request(address, command_text(NineBitCommand::write_eeprom) + std::to_string(location) +
                              delimiter + std::to_string(value));
}

Expected<NineBitCommandLine, std::string> parse_nine_bit_body(std::string_view body) {
  if (body.empty()) return Unexpected(std::string("empty command"));
  const auto command = nine_bit_command(body.front());
  if (!command) return Unexpected("unknown command " + quoted(body.substr(0, 1)));
  body.remove_prefix(1);
  NineBitCommandLine line{*command, std::nullopt, std::nullopt};
  if (*command == NineBitCommand::read_eeprom || *command == NineBitCommand::write_eeprom) {
    line.location = take_number(body);
    if (!line.location) return Unexpected(std::string("no EEPROM location (0..65535)"));
  }
  if (*command == NineBitCommand::write_eeprom) {
    if (body.empty() || !is_nine_bit_delimiter(body.front())) {
      return Unexpected(std::string("no delimiter after the EEPROM location"));
    }
    body.remove_prefix(1);
    line.value = take_number(body);
    if (!line.value) return Unexpected(std::string("no value (0..65535)"));
  }
  if (!body.empty()) return Unexpected("unexpected " + quoted(body) + " after the command");
  return line;
}

std::vector<std::uint8_t> nine_bit_reply_line(std::string_view text) {
  std::vector<std::uint8_t> bytes(text.begin(), text.end());
  bytes.insert(bytes.end(), kCrLf.begin(), kCrLf.end());
  return bytes;
}

Expected<NineBitNumber, ReplyError> parse_nine_bit_number(std::string_view line) {
  std::string_view text = trim(line);
  const bool negative = !text.empty() && text.front() == '-';
  if (!text.empty() && (text.front() == '-' || text.front() == '+')) text.remove_prefix(1);
  std::int64_t magnitude = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), magnitude);
  const std::int64_t value = negative ? -magnitude : magnitude;
  const bool starts_with_digit = !text.empty() && text.front() >= '0' && text.front() <= '9';
  if (!starts_with_digit || ec != std::errc() || end != text.data() + text.size() ||
      value < std::numeric_limits<std::int32_t>::min() ||
      value > std::numeric_limits<std::int32_t>::max()) {
    return Unexpected(ReplyError{ReplyError::Kind::bad_text,
                                 "expected a decimal number, got " + quoted(line)});
  }
  return NineBitNumber{static_cast<std::int32_t>(value), std::string(line)};
}

Expected<std::string, ReplyError> parse_nine_bit_firmware(std::string_view line) {
  const std::string_view text = trim(line);
  if (text.empty()) {
    return Unexpected(ReplyError{ReplyError::Kind::bad_text, "empty firmware revision"});
  }
  return std::string(text);
}

std::size_t NineBitLineParser::feed(std::span<const std::uint8_t> bytes) {
  for (std::uint8_t byte : bytes) take(byte);
  return ready_.size();
}

std::optional<std::string> NineBitLineParser::next() {
  if (ready_.empty()) return std::nullopt;
  std::string line = std::move(ready_.front());
  ready_.pop_front();
  return line;
}

void NineBitLineParser::reset() {
  counters_.bytes_dropped += line_.size() + (after_cr_ ? 1 : 0);
  line_.clear();
  after_cr_ = false;
  overlong_ = false;
  ready_.clear();
}

void NineBitLineParser::take(std::uint8_t byte) {
  if (after_cr_) {
    after_cr_ = false;
    if (byte == '\n') {
      end_line();
      return;
    }
    ++counters_.bytes_dropped;  // a CR not followed by LF is noise
  }
  if (byte == '\r') {
    after_cr_ = true;
  } else if (!is_line_character(byte) || overlong_) {
    ++counters_.bytes_dropped;
  } else if (line_.size() == kMaxLineLength) {
    counters_.bytes_dropped += line_.size() + 1;
    line_.clear();
    overlong_ = true;
  } else {
    line_.push_back(static_cast<char>(byte));
  }
}

void NineBitLineParser::end_line() {
  if (overlong_) {
    overlong_ = false;
    ++counters_.overlong_lines;
    counters_.bytes_dropped += 2;
    return;
  }
  ready_.push_back(std::move(line_));
  line_.clear();
  ++counters_.lines_ok;
}

}  // namespace tiltgate::spectron
