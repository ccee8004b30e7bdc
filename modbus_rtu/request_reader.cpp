#include "modbus_rtu/request_reader.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "driver/modbus_reads.h"
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

}  // namespace

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
