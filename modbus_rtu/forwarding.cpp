#include "modbus_rtu/forwarding.h"

#include "modbus_rtu/adu_framing.h"

namespace tiltgate::modbus_rtu {

namespace {

class MbapForwardedExchange final : public ForwardedExchange {
 public:
  explicit MbapForwardedExchange(Request request)
      : framer_(std::move(request), fresh_transaction_id()) {}

  const std::vector<std::uint8_t>& request_bytes() const override {
    return framer_.request_bytes();
  }
  ReplyFramer& framer() override { return framer_; }
  // The PDU of the frame with this request's transaction and unit ids, unchecked: the client
  // judges its content, as on a serial line.
  Expected<std::vector<std::uint8_t>, std::string> reply_pdu() const override {
    if (!framer_.frame()) return Unexpected{std::string("no reply frame")};
    return framer_.frame()->pdu;
  }

 private:
  MbapReplyFramer framer_;
};

}  // namespace

RtuForwardedExchange::RtuForwardedExchange(Request request)
    : request_(std::move(request)),
      parser_(FrameKind::reply, Expectation{request_.slave, request_.function}) {}

void RtuForwardedExchange::reset() {
  parser_.reset();
  reply_frame_.reset();
  crc_errors_before_ = parser_.counters().crc_errors;
}

bool RtuForwardedExchange::feed(std::span<const std::uint8_t> bytes) {
  if (reply_frame_) return true;  // bytes after the reply are ignored
  parser_.feed(bytes);
  reply_frame_ = parser_.next();
  return reply_frame_.has_value();
}

FramerReport RtuForwardedExchange::report() const {
  FramerReport report;
  if (reply_frame_) report.reply = *reply_frame_;
  report.reply_verdict = "CRC ok";
  if (parser_.counters().crc_errors > crc_errors_before_) report.rejected_verdict = "bad CRC";
  return report;
}

Expected<std::vector<std::uint8_t>, std::string> RtuForwardedExchange::reply_pdu() const {
  if (!reply_frame_) return Unexpected{std::string("no reply frame")};
  // The parser took it whole, from this slave, with a good CRC: drop the address and the CRC.
  const Bytes& frame = *reply_frame_;
  return std::vector<std::uint8_t>(frame.begin() + 1, frame.end() - 2);
}

Expected<std::unique_ptr<ForwardedExchange>, std::string> forward_request(
    std::uint8_t slave, std::span<const std::uint8_t> pdu) {
  // Broadcasts get no reply to relay: pass-through is for one slave at a time.
  if (slave == kBroadcastAddress) return Unexpected{std::string("cannot forward to slave 0")};
  auto request = raw_request(slave, pdu);
  if (!request) return Unexpected{std::string(to_string(request.error()))};
  return std::unique_ptr<ForwardedExchange>(
      std::make_unique<RtuForwardedExchange>(std::move(*request)));
}

Expected<std::unique_ptr<ForwardedExchange>, std::string> forward_mbap_request(
    std::uint8_t unit, std::span<const std::uint8_t> pdu) {
  auto request = AduFraming(Adu::mbap).request_for(
      unit, [pdu](std::uint8_t slave) { return raw_request(slave, pdu); });
  if (!request) return Unexpected{std::string(to_string(request.error()))};
  return std::unique_ptr<ForwardedExchange>(
      std::make_unique<MbapForwardedExchange>(std::move(*request)));
}

}  // namespace tiltgate::modbus_rtu
