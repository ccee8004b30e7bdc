#include "spectron/ascii_codec.h"

#include "spectron/assumptions.h"
#include "spectron/eeprom_map.h"

namespace tiltgate::spectron {
namespace {

constexpr char kHexDigits[] = "0123456789ABCDEF";

std::optional<std::uint8_t> hex_value(char c) {
  if (c >= '0' && c <= '9') return static_cast<std::uint8_t>(c - '0');
  if (c >= 'A' && c <= 'F') return static_cast<std::uint8_t>(c - 'A' + 10);
  if (c >= 'a' && c <= 'f') return static_cast<std::uint8_t>(c - 'a' + 10);
  return std::nullopt;
}

void put_hex(std::string& out, std::uint8_t byte) {
  out += kHexDigits[byte >> 4];
  out += kHexDigits[byte & 0x0F];
}

// Two hex digits at text[at]; the caller has checked they are hex.
std::uint8_t byte_at(std::string_view text, std::size_t at) {
  return static_cast<std::uint8_t>(*hex_value(text[at]) << 4 | *hex_value(text[at + 1]));
}

void put_word(std::vector<std::uint8_t>& data, std::uint16_t word) {
  data.push_back(static_cast<std::uint8_t>(word >> 8));
  data.push_back(static_cast<std::uint8_t>(word));
}

Expected<Done, ArgumentError> check_address(int address) {
  if (address < eeprom::kMinModbusAddress || address > eeprom::kMaxModbusAddress) {
    return Unexpected(ArgumentError{"module address " + std::to_string(address) +
                                    " is out of range 1..250"});
  }
  return Done{};
}

AsciiRequestResult request(int address, AsciiCommand command,
                           std::vector<std::uint8_t> data = {}) {
  if (auto valid = check_address(address); !valid) return Unexpected(valid.error());
  return AsciiFrame{static_cast<std::uint8_t>(address), static_cast<std::uint8_t>(command),
                    std::move(data)};
}

std::string command_text(std::uint8_t command) {
  const char* name = ascii_command_name(command);
  std::string text = "0x";
  put_hex(text, command);
  return name ? text + " (" + name + ")" : text;
}

// `reply` answers `request`, whose command must be `expected`, with `data_bytes` of data.
Expected<Done, ReplyError> check_reply(const AsciiFrame& reply, const AsciiFrame& request,
                                       AsciiCommand expected, std::size_t data_bytes) {
  const auto want = static_cast<std::uint8_t>(expected);
  if (request.command != want || reply.command != want) {
    return Unexpected(ReplyError{ReplyError::Kind::wrong_command,
                                 "expected " + command_text(want) + ", got " +
                                     command_text(reply.command)});
  }
  if (reply.address != request.address) {
    return Unexpected(ReplyError{ReplyError::Kind::wrong_address,
                                 "expected module " + std::to_string(request.address) +
                                     ", got " + std::to_string(reply.address)});
  }
  if (reply.data.size() != data_bytes) {
    return Unexpected(ReplyError{ReplyError::Kind::wrong_length,
                                 "expected " + std::to_string(data_bytes) + " data bytes, got " +
                                     std::to_string(reply.data.size())});
  }
  return Done{};
}

Expected<std::uint16_t, ReplyError> word_reply(const AsciiFrame& reply, const AsciiFrame& request,
                                               AsciiCommand expected) {
  if (auto valid = check_reply(reply, request, expected, kReplyWordDigits / 2); !valid) {
    return Unexpected(valid.error());
  }
  return *word_at(reply, 0);
}

Expected<std::int16_t, ReplyError> signed_word_reply(const AsciiFrame& reply,
                                                     const AsciiFrame& request,
                                                     AsciiCommand expected) {
  auto word = word_reply(reply, request, expected);
  if (!word) return Unexpected(word.error());
  return static_cast<std::int16_t>(*word);  // two's complement (A6)
}

}  // namespace

const char* ascii_command_name(std::uint8_t command) {
  switch (static_cast<AsciiCommand>(command)) {
    case AsciiCommand::reset: return "reset";
    case AsciiCommand::read_sensor: return "read sensor";
    case AsciiCommand::read_temperature: return "read temperature";
    case AsciiCommand::write_eeprom: return "write EEPROM";
    case AsciiCommand::read_eeprom: return "read EEPROM";
    case AsciiCommand::revision: return "send revision";
  }
  return nullptr;
}

std::uint8_t lrc(std::string_view characters) {
  std::uint8_t sum = 0;
  for (char c : characters) sum = static_cast<std::uint8_t>(sum + static_cast<std::uint8_t>(c));
  return static_cast<std::uint8_t>(-sum);
}

std::string encode_text(const AsciiFrame& frame) {
  std::string body;
  put_hex(body, frame.address);
  put_hex(body, frame.command);
  for (std::uint8_t byte : frame.data) put_hex(body, byte);
  std::string text = ":" + body;
  put_hex(text, lrc(body));
  return text + "\r\n";
}

std::vector<std::uint8_t> encode(const AsciiFrame& frame) {
  const std::string text = encode_text(frame);
  return std::vector<std::uint8_t>(text.begin(), text.end());
}

const char* to_string(AsciiDecodeError error) {
  switch (error) {
    case AsciiDecodeError::no_start: return "frame does not start with ':'";
    case AsciiDecodeError::no_end: return "frame does not end with CR LF";
    case AsciiDecodeError::too_short: return "frame too short";
    case AsciiDecodeError::too_long: return "frame too long";
    case AsciiDecodeError::odd_digits: return "odd number of hex digits";
    case AsciiDecodeError::not_hex: return "not a hex digit";
    case AsciiDecodeError::bad_lrc: return "bad LRC";
  }
  return "unknown error";
}

Expected<AsciiFrame, AsciiDecodeError> decode(std::string_view text) {
  if (text.size() > kMaxFrameLength) return Unexpected(AsciiDecodeError::too_long);
  if (text.empty() || text.front() != ':') return Unexpected(AsciiDecodeError::no_start);
  if (text.size() < 3 || text.substr(text.size() - 2) != "\r\n") {
    return Unexpected(AsciiDecodeError::no_end);
  }
  const std::string_view digits = text.substr(1, text.size() - 3);
  for (char c : digits) {
    if (!hex_value(c)) return Unexpected(AsciiDecodeError::not_hex);
  }
  if (digits.size() % 2 != 0) return Unexpected(AsciiDecodeError::odd_digits);
  if (text.size() < kMinFrameLength) return Unexpected(AsciiDecodeError::too_short);
  const std::string_view covered = digits.substr(0, digits.size() - 2);
  if (lrc(covered) != byte_at(digits, digits.size() - 2)) {
    return Unexpected(AsciiDecodeError::bad_lrc);
  }
  AsciiFrame frame{byte_at(covered, 0), byte_at(covered, 2), {}};
  for (std::size_t at = 4; at < covered.size(); at += 2) frame.data.push_back(byte_at(covered, at));
  return frame;
}

bool is_reply_to(const AsciiFrame& reply, const AsciiFrame& request) {
  return reply.address == request.address && reply.command == request.command;
}

AsciiRequestResult ascii_reset_request(int address) {
  return request(address, AsciiCommand::reset);
}

AsciiRequestResult ascii_read_sensor_request(int address) {
  return request(address, AsciiCommand::read_sensor);
}

AsciiRequestResult ascii_read_temperature_request(int address) {
  return request(address, AsciiCommand::read_temperature);
}

AsciiRequestResult ascii_revision_request(int address) {
  return request(address, AsciiCommand::revision);
}

AsciiRequestResult ascii_read_eeprom_request(int address, std::int64_t location) {
  if (auto known = eeprom::check_location(location); !known) {
    return Unexpected(ArgumentError{known.error()});
  }
  std::vector<std::uint8_t> data;
  put_word(data, static_cast<std::uint16_t>(location));
  return request(address, AsciiCommand::read_eeprom, std::move(data));
}

AsciiRequestResult ascii_write_eeprom_request(int address, std::int64_t location,
                                              std::int64_t value) {
  if (auto known = eeprom::check_location(location); !known) {
    return Unexpected(ArgumentError{known.error()});
  }
  if (value < 0 || value > eeprom::kMaxValue) {
    return Unexpected(ArgumentError{"EEPROM value " + std::to_string(value) +
                                    " is out of range 0..65535"});
  }
  std::vector<std::uint8_t> data;
  put_word(data, static_cast<std::uint16_t>(location));
  put_word(data, static_cast<std::uint16_t>(value));
  return request(address, AsciiCommand::write_eeprom, std::move(data));
}

Expected<Done, ReplyError> parse_ascii_ack(const AsciiFrame& reply, const AsciiFrame& request) {
  const auto command = static_cast<AsciiCommand>(request.command);
  if (command != AsciiCommand::reset && command != AsciiCommand::write_eeprom) {
    return Unexpected(ReplyError{ReplyError::Kind::wrong_command,
                                 command_text(request.command) + " is not answered by an echo"});
  }
  return check_reply(reply, request, command, 0);
}

Expected<std::int16_t, ReplyError> parse_ascii_sensor_reply(const AsciiFrame& reply,
                                                            const AsciiFrame& request) {
  return signed_word_reply(reply, request, AsciiCommand::read_sensor);
}

Expected<std::int16_t, ReplyError> parse_ascii_temperature_reply(const AsciiFrame& reply,
                                                                 const AsciiFrame& request) {
  return signed_word_reply(reply, request, AsciiCommand::read_temperature);
}

Expected<std::uint16_t, ReplyError> parse_ascii_eeprom_reply(const AsciiFrame& reply,
                                                             const AsciiFrame& request) {
  return word_reply(reply, request, AsciiCommand::read_eeprom);
}

Expected<std::string, ReplyError> parse_ascii_revision_reply(const AsciiFrame& reply,
                                                             const AsciiFrame& request) {
  auto word = word_reply(reply, request, AsciiCommand::revision);
  if (!word) return Unexpected(word.error());
  return revision_text(*word);
}

std::string revision_text(std::uint16_t word) {
  std::string text;
  put_hex(text, static_cast<std::uint8_t>(word >> 8));
  text += '.';
  put_hex(text, static_cast<std::uint8_t>(word));
  return text;
}

AsciiFrame make_ascii_ack(std::uint8_t address, AsciiCommand command) {
  return AsciiFrame{address, static_cast<std::uint8_t>(command), {}};
}

AsciiFrame make_ascii_word_reply(std::uint8_t address, AsciiCommand command, std::uint16_t word) {
  AsciiFrame frame{address, static_cast<std::uint8_t>(command), {}};
  put_word(frame.data, word);
  return frame;
}

std::optional<std::uint16_t> word_at(const AsciiFrame& frame, std::size_t index) {
  if (2 * index + 1 >= frame.data.size()) return std::nullopt;
  return static_cast<std::uint16_t>(frame.data[2 * index] << 8 | frame.data[2 * index + 1]);
}

}  // namespace tiltgate::spectron
