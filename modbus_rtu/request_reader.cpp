#include "modbus_rtu/request_reader.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>

#include "driver/modbus_reads.h"
#include "modbus_rtu/codec.h"
#include "modbus_rtu/crc.h"
#include "modbus_rtu/mbap_codec.h"

namespace tiltgate::modbus_rtu {

namespace {

// An RTU frame: the address, the PDU, the CRC.
constexpr std::size_t kRtuOverhead = 3;

CarriedRequest carried(std::uint32_t address, std::span<const std::uint8_t> pdu) {
  CarriedRequest request;
  request.address = address;
  request.may_change = !reads_only(pdu);
  request.function = fmt::format("function {:02X}", pdu[0]);
  request.data = fmt::format("{:02X}", fmt::join(pdu.subspan(1), ""));
  return request;
}

std::optional<std::string> refusal(std::span<const std::uint8_t> pdu) {
  if (pdu.empty() || (pdu[0] & 0x80) == 0) return std::nullopt;
  return fmt::format("nak 0x{:02X}", pdu.size() > 1 ? pdu[1] : 0);
}

// The PDU of one whole MBAP frame; empty when the bytes are not one.
std::span<const std::uint8_t> mbap_pdu(std::span<const std::uint8_t> frame) {
  if (frame.size() <= kMbapHeaderSize || frame[2] != 0 || frame[3] != 0) return {};
  const std::size_t length = std::size_t(frame[4]) << 8 | frame[5];
  if (length + 6 != frame.size()) return {};
  return frame.subspan(kMbapHeaderSize);
}

// The most values a reply's text shows; "..." stands for the rest.
constexpr std::size_t kValuesShown = 10;

// What a checked reply to the request whose PDU is `asked` says.
std::optional<std::string> reply_text(const Reply& reply, std::span<const std::uint8_t> asked) {
  if (reply.exception) return std::nullopt;
  switch (reply.function) {
    case 0x03:
    case 0x04: {
      const std::size_t shown = std::min(reply.registers.size(), kValuesShown);
      return fmt::format("values {}{}",
                         fmt::join(reply.registers.begin(), reply.registers.begin() + long(shown), ", "),
                         reply.registers.size() > shown ? ", ..." : "");
    }
    case 0x01:
    case 0x02: {
      if (reply.pdu.size() < 3 || asked.size() < 5) return std::nullopt;
      // As many as were asked for: the last byte's high bits are padding.
      const std::size_t count = std::size_t(asked[3]) << 8 | asked[4];
      std::vector<int> bits;
      for (std::size_t i = 0; i < count && 2 + i / 8 < reply.pdu.size(); ++i)
        bits.push_back(reply.pdu[2 + i / 8] >> (i % 8) & 1);
      const std::size_t shown = std::min(bits.size(), kValuesShown);
      return fmt::format("bits {}{}", fmt::join(bits.begin(), bits.begin() + long(shown), " "),
                         bits.size() > shown ? " ..." : "");
    }
    case 0x05:
    case 0x06:
    case 0x0F:
    case 0x10:
      return std::string("written");
    case 0x08:
      return std::string("echo");
    default:
      return std::nullopt;
  }
}

}  // namespace

std::optional<std::string> read_rtu_reply(std::span<const std::uint8_t> request,
                                          std::span<const std::uint8_t> reply) {
  if (request.size() <= kRtuOverhead || !crc_ok(request)) return std::nullopt;
  const Request asked{request[0], request[1], Bytes(request.begin(), request.end())};
  const auto checked = parse_reply(asked, reply);
  if (!checked) return std::nullopt;
  return reply_text(*checked, request.subspan(1, request.size() - kRtuOverhead));
}

std::optional<std::string> read_mbap_reply(std::span<const std::uint8_t> request,
                                           std::span<const std::uint8_t> reply) {
  const auto asked_pdu = mbap_pdu(request);
  const auto reply_pdu = mbap_pdu(reply);
  if (asked_pdu.empty() || reply_pdu.empty() || request[6] != reply[6] ||
      request[0] != reply[0] || request[1] != reply[1])
    return std::nullopt;
  // The request as an RTU frame (its CRC is not checked here): what parse_reply_pdu reads the
  // asked function and counts from.
  Bytes frame{request[6]};
  frame.insert(frame.end(), asked_pdu.begin(), asked_pdu.end());
  frame.push_back(0);
  frame.push_back(0);
  const Request asked{request[6], asked_pdu[0], std::move(frame)};
  const auto checked = parse_reply_pdu(asked, reply_pdu);
  if (!checked) return std::nullopt;
  return reply_text(*checked, asked_pdu);
}

std::optional<CarriedRequest> read_rtu_request(std::span<const std::uint8_t> request) {
  if (request.size() <= kRtuOverhead || !crc_ok(request)) return std::nullopt;
  return carried(request[0], request.subspan(1, request.size() - kRtuOverhead));
}

std::optional<std::string> read_rtu_refusal(std::span<const std::uint8_t> reply) {
  if (reply.size() <= kRtuOverhead || !crc_ok(reply)) return std::nullopt;
  return refusal(reply.subspan(1, reply.size() - kRtuOverhead));
}

std::optional<CarriedRequest> read_mbap_request(std::span<const std::uint8_t> request) {
  const auto pdu = mbap_pdu(request);
  if (pdu.empty()) return std::nullopt;
  return carried(request[6], pdu);
}

std::optional<std::string> read_mbap_refusal(std::span<const std::uint8_t> reply) {
  return refusal(mbap_pdu(reply));
}

}  // namespace tiltgate::modbus_rtu
