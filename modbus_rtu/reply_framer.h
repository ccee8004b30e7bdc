// Tells the Line when the reply to one Modbus RTU request has arrived: the first frame with a
// good CRC from the slave asked, with the request's function code or its exception. Garbage
// and other slaves' frames before it are skipped; bad CRCs are counted. The frame is then
// checked as that request's reply (modbus_rtu/codec.h): a frame that fails those checks (a
// wrong byte count, a write that does not echo) still ends the wait, with the error to report,
// since waiting on would only turn a protocol error into a time-out.
#pragma once

#include <optional>

#include "driver/line.h"
#include "modbus_rtu/codec.h"
#include "modbus_rtu/frame_parser.h"

namespace tiltgate::modbus_rtu {

// One Modbus request as its framing sends it, and the framer that finds its checked reply: the
// RTU frame below, or an MBAP frame (modbus_rtu/mbap_reply_framer.h). The driver, scan and raw
// exchanges hold one of these and never look at the framing.
class ModbusReplyFramer : public ReplyFramer {
 public:
  // The request as it goes on the wire.
  virtual const Bytes& request_bytes() const = 0;
  // The checked reply once feed() returned true.
  virtual const std::optional<Expected<Reply, CodecError>>& reply() const = 0;
  // Frames that failed the framing's integrity check (an RTU CRC; MBAP has none of its own).
  virtual std::uint64_t crc_errors() const = 0;
};

class RtuReplyFramer : public ModbusReplyFramer {
 public:
  explicit RtuReplyFramer(Request request)
      : request_(std::move(request)),
        parser_(FrameKind::reply, Expectation{request_.slave, request_.function}) {}

  const Bytes& request_bytes() const override { return request_.frame; }

  void reset() override {
    parser_.reset();
    reply_.reset();
    reply_frame_.clear();
    crc_errors_before_ = parser_.counters().crc_errors;
  }

  bool feed(std::span<const std::uint8_t> bytes) override {
    if (reply_) return true;  // bytes after the reply are ignored
    parser_.feed(bytes);
    if (auto frame = parser_.next()) {
      reply_.emplace(parse_reply(request_, *frame));
      reply_frame_ = std::move(*frame);
    }
    return reply_.has_value();
  }

  FramerReport report() const override {
    FramerReport report;
    report.reply = reply_frame_;
    report.reply_verdict = "CRC ok";
    if (reply_ && !*reply_) {
      report.reply_verdict += std::string(", but ") + to_string(reply_->error());
    }
    if (parser_.counters().crc_errors > crc_errors_before_) report.rejected_verdict = "bad CRC";
    return report;
  }

  const std::optional<Expected<Reply, CodecError>>& reply() const override { return reply_; }
  const Request& request() const { return request_; }
  std::uint64_t crc_errors() const override { return parser_.counters().crc_errors; }

 private:
  Request request_;
  RtuFrameParser parser_;
  std::optional<Expected<Reply, CodecError>> reply_;
  Bytes reply_frame_;                    // the reply as received, for report()
  std::uint64_t crc_errors_before_ = 0;  // the parser's count at reset()
};

}  // namespace tiltgate::modbus_rtu
