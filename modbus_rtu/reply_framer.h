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

class RtuReplyFramer : public ReplyFramer {
 public:
  explicit RtuReplyFramer(Request request)
      : request_(std::move(request)),
        parser_(FrameKind::reply, Expectation{request_.slave, request_.function}) {}

  void reset() override {
    parser_.reset();
    reply_.reset();
  }

  bool feed(std::span<const std::uint8_t> bytes) override {
    if (reply_) return true;  // bytes after the reply are ignored
    parser_.feed(bytes);
    if (auto frame = parser_.next()) reply_.emplace(parse_reply(request_, *frame));
    return reply_.has_value();
  }

  // The checked reply once feed() returned true.
  const std::optional<Expected<Reply, CodecError>>& reply() const { return reply_; }
  const Request& request() const { return request_; }
  std::uint64_t crc_errors() const { return parser_.counters().crc_errors; }

 private:
  Request request_;
  RtuFrameParser parser_;
  std::optional<Expected<Reply, CodecError>> reply_;
};

}  // namespace tiltgate::modbus_rtu
