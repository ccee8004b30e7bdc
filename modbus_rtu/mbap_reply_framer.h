// Tells the Line when the reply to one Modbus TCP request has arrived: the first MBAP frame with
// the request's transaction id and unit id (modbus_rtu/mbap_codec.h). Every other frame is
// dropped: a late reply to an earlier request carries that request's transaction id, and the
// id changes with every request (AduFraming, modbus_rtu/adu_framing.h), so it is never taken for
// this one. The frame's PDU is then checked as the request's reply by the RTU codec's PDU
// checks (modbus_rtu/codec.h), which end the wait with their error as on a serial line.
#pragma once

#include <optional>

#include "modbus_rtu/mbap_codec.h"
#include "modbus_rtu/reply_framer.h"

namespace tiltgate::modbus_rtu {

class MbapReplyFramer final : public ModbusReplyFramer {
 public:
  // `request` as the RTU codec built it for the unit id (its slave); `transaction`: this
  // request's id.
  MbapReplyFramer(Request request, std::uint16_t transaction);

  const Bytes& request_bytes() const override { return bytes_; }
  const std::optional<Expected<Reply, CodecError>>& reply() const override { return reply_; }
  std::uint64_t crc_errors() const override { return 0; }  // TCP checks its own bytes

  void reset() override;
  bool feed(std::span<const std::uint8_t> bytes) override;
  FramerReport report() const override;

  // The frame taken as the reply, as the device sent it (a pass-through relays its PDU).
  const std::optional<MbapFrame>& frame() const { return frame_; }
  // Frames dropped since reset(): other transactions' or other units' replies.
  std::uint64_t frames_dropped() const { return dropped_; }

 private:
  Request request_;
  std::uint16_t transaction_;
  Bytes bytes_;
  MbapStream stream_;
  std::optional<MbapFrame> frame_;
  std::optional<Expected<Reply, CodecError>> reply_;
  std::uint64_t dropped_ = 0;
  std::uint64_t discarded_before_ = 0;  // the stream's count at reset()
};

}  // namespace tiltgate::modbus_rtu
