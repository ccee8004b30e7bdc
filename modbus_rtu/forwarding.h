// Modbus TCP pass-through on a Modbus RTU bus: a request PDU framed unchanged for one slave
// (address, PDU, CRC), and the reply PDU taken from the first good frame from that slave for
// the request's function or its exception. The reply is relayed as the device sent it: the
// gateway checks only that it is a whole frame with a good CRC (the client judges its
// content), so functions the gateway itself never uses (08, 17, ...) pass through too, their
// length found by CRC (modbus_rtu/frame_length.h). Garbage and other slaves' frames before
// the reply are skipped, as for the gateway's own requests.
#pragma once

#include <optional>

#include "driver/forwarded_exchange.h"
#include "modbus_rtu/codec.h"
#include "modbus_rtu/frame_parser.h"
#include "modbus_rtu/mbap_reply_framer.h"

namespace tiltgate::modbus_rtu {

class RtuForwardedExchange final : public ForwardedExchange, private ReplyFramer {
 public:
  explicit RtuForwardedExchange(Request request);

  const std::vector<std::uint8_t>& request_bytes() const override { return request_.frame; }
  ReplyFramer& framer() override { return *this; }
  Expected<std::vector<std::uint8_t>, std::string> reply_pdu() const override;

 private:
  void reset() override;
  bool feed(std::span<const std::uint8_t> bytes) override;
  FramerReport report() const override;

  Request request_;
  RtuFrameParser parser_;
  std::optional<Bytes> reply_frame_;
  std::uint64_t crc_errors_before_ = 0;  // the parser's count at reset()
};

// ProtocolDescriptor::forward of the modbus-rtu protocol: slave 1..247, a PDU of 1..253 bytes.
Expected<std::unique_ptr<ForwardedExchange>, std::string> forward_request(
    std::uint8_t slave, std::span<const std::uint8_t> pdu);

// ProtocolDescriptor::forward of the modbus-tcp protocol: the PDU in an MBAP frame for unit id
// 0..255 with a transaction id of its own, and the reply PDU of the first frame with that
// transaction id and unit id, relayed as the device sent it (modbus_rtu/mbap_reply_framer.h).
Expected<std::unique_ptr<ForwardedExchange>, std::string> forward_mbap_request(
    std::uint8_t unit, std::span<const std::uint8_t> pdu);

}  // namespace tiltgate::modbus_rtu
