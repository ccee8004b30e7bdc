// Tells the Line when the reply to one Rieker request has arrived: the first good frame that
// answers that request. Frames from other sensors (a collision, a late reply to an earlier
// request) are skipped; bad CRCs are counted. For the trace log, a stretch of bytes that formed
// no frame with a good CRC is "bad CRC": without a start marker, noise and a corrupted frame
// look alike.
#pragma once

#include <optional>

#include "driver/line.h"
#include "rieker/frame_parser.h"

namespace tiltgate::rieker {

class RiekerReplyFramer : public ReplyFramer {
 public:
  explicit RiekerReplyFramer(Frame request) : request_(std::move(request)) {}

  void reset() override {
    parser_.reset();
    reply_.reset();
    crc_errors_before_ = parser_.counters().crc_errors;
  }

  bool feed(std::span<const std::uint8_t> bytes) override {
    parser_.feed(bytes);
    while (!reply_) {
      auto frame = parser_.next();
      if (!frame) break;
      if (is_reply_to(*frame, request_)) reply_ = std::move(*frame);
    }
    return reply_.has_value();
  }

  FramerReport report() const override {
    FramerReport report;
    // A frame with a good CRC encodes back to the very bytes received.
    if (reply_) report.reply = encode(*reply_);
    report.reply_verdict = "CRC ok";
    if (parser_.counters().crc_errors > crc_errors_before_) report.rejected_verdict = "bad CRC";
    return report;
  }

  const std::optional<Frame>& reply() const { return reply_; }
  std::uint64_t crc_errors() const { return parser_.counters().crc_errors; }

 private:
  Frame request_;
  RiekerFrameParser parser_;
  std::optional<Frame> reply_;
  std::uint64_t crc_errors_before_ = 0;  // the parser's count at reset()
};

}  // namespace tiltgate::rieker
