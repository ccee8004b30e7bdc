// Tells the Line when the reply to one Rieker request has arrived: the first good frame that
// answers that request. Frames from other sensors (a collision, a late reply to an earlier
// request) are skipped; bad CRCs are counted.
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

  const std::optional<Frame>& reply() const { return reply_; }
  std::uint64_t crc_errors() const { return parser_.counters().crc_errors; }

 private:
  Frame request_;
  RiekerFrameParser parser_;
  std::optional<Frame> reply_;
};

}  // namespace tiltgate::rieker
