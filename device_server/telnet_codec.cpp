#include "device_server/telnet_codec.h"

namespace tiltgate::telnet {

void escape(std::span<const std::uint8_t> data, std::vector<std::uint8_t>& out) {
  for (const std::uint8_t byte : data) {
    out.push_back(byte);
    if (byte == kIac) out.push_back(kIac);
  }
}

std::vector<std::uint8_t> negotiation(std::uint8_t verb, std::uint8_t option) {
  return {kIac, verb, option};
}

std::vector<std::uint8_t> subnegotiation(std::uint8_t option,
                                         std::span<const std::uint8_t> payload) {
  std::vector<std::uint8_t> out{kIac, kSb, option};
  escape(payload, out);
  out.push_back(kIac);
  out.push_back(kSe);
  return out;
}

std::size_t Reader::take(std::span<std::uint8_t> chunk, std::vector<Command>& commands) {
  std::size_t kept = 0;
  for (const std::uint8_t byte : chunk) {
    switch (state_) {
      case State::data:
        if (byte == kIac) {
          state_ = State::iac;
        } else {
          chunk[kept++] = byte;
        }
        break;
      case State::iac:
        if (byte == kIac) {  // an escaped 0xFF data byte
          chunk[kept++] = byte;
          state_ = State::data;
        } else if (byte == kWill || byte == kWont || byte == kDo || byte == kDont) {
          pending_ = Command{.verb = byte, .option = 0, .payload = {}};
          state_ = State::verb;
        } else if (byte == kSb) {
          pending_ = Command{.verb = kSb, .option = 0, .payload = {}};
          state_ = State::sb_option;
        } else {
          state_ = State::data;  // NOP, GA, a stray SE, ...: nothing we act on
        }
        break;
      case State::verb:
        pending_.option = byte;
        commands.push_back(std::move(pending_));
        state_ = State::data;
        break;
      case State::sb_option:
        pending_.option = byte;
        state_ = State::sb;
        break;
      case State::sb:
        if (byte == kIac) {
          state_ = State::sb_iac;
        } else if (pending_.payload.size() < kMaxPayload) {
          pending_.payload.push_back(byte);
        }
        break;
      case State::sb_iac:
        if (byte == kSe) {
          commands.push_back(std::move(pending_));
          state_ = State::data;
        } else {
          // IAC IAC is an escaped 0xFF; anything else is a malformed subnegotiation, whose
          // byte is kept as data of it rather than ending it early.
          if (pending_.payload.size() < kMaxPayload) pending_.payload.push_back(byte);
          state_ = State::sb;
        }
        break;
    }
  }
  return kept;
}

}  // namespace tiltgate::telnet
