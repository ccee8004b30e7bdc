#include "spectron/dyna_transactions.h"

#include "spectron/ascii_codec.h"
#include "spectron/eeprom_map.h"
#include "spectron/nine_bit_codec.h"

namespace tiltgate::spectron {
namespace {

using Kind = DynaRequest::Kind;

Expected<NineBitRequest, std::string> nine_bit_request(int address, const DynaRequest& request) {
  if (address < 0 || address > eeprom::kMaxNineBitAddress) {
    return Unexpected("module address " + std::to_string(address) + " is out of range 0..255");
  }
  const auto to = static_cast<std::uint8_t>(address);
  NineBitRequestResult built = NineBitRequest{};
  switch (request.kind) {
    case Kind::reset: built = nine_bit_reset_request(to); break;
    case Kind::read_sensor: built = nine_bit_read_sensor_request(to); break;
    case Kind::read_temperature: built = nine_bit_read_temperature_request(to); break;
    case Kind::firmware: built = nine_bit_firmware_request(to); break;
    case Kind::read_eeprom: built = nine_bit_read_eeprom_request(to, request.location); break;
    case Kind::write_eeprom:
      built = nine_bit_write_eeprom_request(to, request.location, request.value);
      break;
  }
  if (!built) return Unexpected(built.error().message);
  return *built;
}

Expected<AsciiFrame, std::string> ascii_request(int address, const DynaRequest& request) {
  AsciiRequestResult built = AsciiFrame{};
  switch (request.kind) {
    case Kind::reset: built = ascii_reset_request(address); break;
    case Kind::read_sensor: built = ascii_read_sensor_request(address); break;
    case Kind::read_temperature: built = ascii_read_temperature_request(address); break;
    case Kind::firmware: built = ascii_revision_request(address); break;
    case Kind::read_eeprom: built = ascii_read_eeprom_request(address, request.location); break;
    case Kind::write_eeprom:
      built = ascii_write_eeprom_request(address, request.location, request.value);
      break;
  }
  if (!built) return Unexpected(built.error().message);
  return *built;
}

template <class T>
Expected<DynaAnswer, ReplyError> number_answer(const Expected<T, ReplyError>& parsed) {
  if (!parsed) return Unexpected(parsed.error());
  return DynaAnswer{static_cast<std::int32_t>(*parsed), {}};
}

Expected<DynaAnswer, ReplyError> text_answer(const Expected<std::string, ReplyError>& parsed) {
  if (!parsed) return Unexpected(parsed.error());
  return DynaAnswer{0, *parsed};
}

}  // namespace

const char* request_name(DynaRequest::Kind kind) {
  switch (kind) {
    case Kind::reset: return "reset";
    case Kind::read_sensor: return "read sensor";
    case Kind::read_temperature: return "read temperature";
    case Kind::read_eeprom: return "read EEPROM";
    case Kind::write_eeprom: return "write EEPROM";
    case Kind::firmware: return "firmware revision";
  }
  return "request";
}

Expected<DynaTransaction, std::string> DynaTransaction::make(Protocol protocol, int address,
                                                             const DynaRequest& request) {
  DynaTransaction transaction(protocol, request);
  if (protocol == Protocol::nine_bit) {
    auto built = nine_bit_request(address, request);
    if (!built) return Unexpected(built.error());
    transaction.bytes_ = wire_bytes(*built);
    transaction.address_bytes_ = kNineBitAddressBytes;
    transaction.nine_bit_ = std::make_unique<NineBitReplyFramer>();
  } else {
    auto built = ascii_request(address, request);
    if (!built) return Unexpected(built.error());
    transaction.bytes_ = encode(*built);
    transaction.ascii_request_ = *built;
    transaction.ascii_ = std::make_unique<AsciiReplyFramer>(*built);
  }
  return transaction;
}

LineRequest DynaTransaction::line_request() const {
  LineRequest request;
  request.bytes = bytes_;
  request.address_bytes = address_bytes_;
  if (nine_bit_) {
    request.framer = nine_bit_.get();
  } else {
    request.framer = ascii_.get();
  }
  return request;
}

std::uint64_t DynaTransaction::checksum_errors() const {
  return ascii_ ? ascii_->lrc_errors() : 0;
}

Expected<DynaAnswer, ReplyError> DynaTransaction::answer() const {
  if (nine_bit_ && nine_bit_->reply()) return nine_bit_answer(*nine_bit_->reply());
  if (ascii_ && ascii_->reply()) return ascii_answer(*ascii_->reply());
  return Unexpected(ReplyError{ReplyError::Kind::bad_text, "no reply received"});
}

// A4: reset and write acknowledge with any line; numbers are decimal; "F" is free text.
Expected<DynaAnswer, ReplyError> DynaTransaction::nine_bit_answer(const std::string& line) const {
  switch (request_.kind) {
    case Kind::reset:
    case Kind::write_eeprom: return DynaAnswer{};
    case Kind::firmware: return text_answer(parse_nine_bit_firmware(line));
    case Kind::read_sensor:
    case Kind::read_temperature:
    case Kind::read_eeprom: break;
  }
  auto number = parse_nine_bit_number(line);
  if (!number) return Unexpected(number.error());
  return DynaAnswer{number->value, {}};
}

Expected<DynaAnswer, ReplyError> DynaTransaction::ascii_answer(const AsciiFrame& reply) const {
  const AsciiFrame& sent = ascii_request_;
  switch (request_.kind) {
    case Kind::reset:
    case Kind::write_eeprom: {
      auto ack = parse_ascii_ack(reply, sent);
      if (!ack) return Unexpected(ack.error());
      return DynaAnswer{};
    }
    case Kind::read_sensor: return number_answer(parse_ascii_sensor_reply(reply, sent));
    case Kind::read_temperature: return number_answer(parse_ascii_temperature_reply(reply, sent));
    case Kind::read_eeprom: return number_answer(parse_ascii_eeprom_reply(reply, sent));
    case Kind::firmware: return text_answer(parse_ascii_revision_reply(reply, sent));
  }
  return Unexpected(ReplyError{ReplyError::Kind::wrong_command, "unknown request"});
}

}  // namespace tiltgate::spectron
