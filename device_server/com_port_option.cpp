#include "device_server/com_port_option.h"

#include <fmt/format.h>

namespace tiltgate::rfc2217 {

namespace {

constexpr unsigned bit_of(std::uint8_t command) { return 1u << (command - kSetBaudrate); }

const char* parity_name(std::uint32_t code) {
  switch (code) {
    case 1: return "none";
    case 2: return "odd";
    case 3: return "even";
    case 4: return "mark";
    case 5: return "space";
    default: return "unknown";
  }
}

}  // namespace

std::uint8_t parity_code(Parity parity) {
  switch (parity) {
    case Parity::none: return 1;
    case Parity::odd: return 2;
    case Parity::even: return 3;
    case Parity::mark: return 4;
    case Parity::space: return 5;
  }
  return 1;
}

std::vector<std::vector<std::uint8_t>> set_requests(const PortSetting& setting) {
  const std::uint32_t baud = setting.baud;
  return {
      {kSetBaudrate, std::uint8_t(baud >> 24), std::uint8_t(baud >> 16), std::uint8_t(baud >> 8),
       std::uint8_t(baud)},
      {kSetDatasize, setting.data_bits},
      {kSetParity, parity_code(setting.parity)},
      {kSetStopsize, setting.stop_bits},
      {kSetControl, kNoFlowControl},
  };
}

std::optional<Answer> read_answer(std::span<const std::uint8_t> payload) {
  if (payload.size() < 2) return std::nullopt;
  const std::uint8_t code = payload[0];
  if (code <= kServerOffset) return std::nullopt;
  Answer answer{.command = std::uint8_t(code - kServerOffset), .value = 0};
  if (answer.command == kSetBaudrate) {
    if (payload.size() < 5) return std::nullopt;
    answer.value = std::uint32_t(payload[1]) << 24 | std::uint32_t(payload[2]) << 16 |
                   std::uint32_t(payload[3]) << 8 | payload[4];
  } else {
    answer.value = payload[1];
  }
  return answer;
}

void Acknowledgements::take(const Answer& answer) {
  std::uint32_t asked = 0;
  std::string what;
  switch (answer.command) {
    case kSetBaudrate:
      asked = asked_.baud;
      what = fmt::format("{} baud, not {}", answer.value, asked);
      break;
    case kSetDatasize:
      asked = asked_.data_bits;
      what = fmt::format("{} data bits, not {}", answer.value, asked);
      break;
    case kSetParity:
      asked = parity_code(asked_.parity);
      what = fmt::format("parity {}, not {}", parity_name(answer.value), parity_name(asked));
      break;
    case kSetStopsize:
      asked = asked_.stop_bits;
      what = fmt::format("{} stop bits (code), not {}", answer.value, asked);
      break;
    default: return;  // SET-CONTROL and notifications: not what the line needs confirmed
  }
  if (answer.value == asked) {
    confirmed_ |= bit_of(answer.command);
  } else if (!refused_) {
    refused_ = "the server set " + what;
  }
}

std::string Acknowledgements::missing() const {
  std::string text;
  const auto add = [&](std::uint8_t command, const char* name) {
    if (confirmed_ & bit_of(command)) return;
    if (!text.empty()) text += ", ";
    text += name;
  };
  add(kSetBaudrate, "baud rate");
  add(kSetDatasize, "data size");
  add(kSetParity, "parity");
  add(kSetStopsize, "stop bits");
  return text;
}

}  // namespace tiltgate::rfc2217
