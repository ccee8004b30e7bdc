#include "modbus_rtu/mbap_reply_framer.h"

#include <fmt/format.h>

namespace tiltgate::modbus_rtu {

MbapReplyFramer::MbapReplyFramer(Request request, std::uint16_t transaction)
    : request_(std::move(request)), transaction_(transaction) {
  const std::span<const std::uint8_t> pdu = request_pdu(request_);
  bytes_ = mbap_bytes(MbapFrame{transaction_, request_.slave, Bytes(pdu.begin(), pdu.end())});
}

void MbapReplyFramer::reset() {
  stream_.reset();
  discarded_before_ = stream_.bytes_discarded();
  frame_.reset();
  reply_.reset();
  dropped_ = 0;
}

bool MbapReplyFramer::feed(std::span<const std::uint8_t> bytes) {
  if (reply_) return true;  // bytes after the reply are ignored
  stream_.feed(bytes);
  while (auto frame = stream_.next()) {
    if (frame->transaction != transaction_ || frame->unit != request_.slave) {
      ++dropped_;
      continue;
    }
    reply_.emplace(parse_reply_pdu(request_, frame->pdu));
    frame_ = std::move(*frame);
    return true;
  }
  return false;
}

FramerReport MbapReplyFramer::report() const {
  FramerReport report;
  if (frame_) report.reply = mbap_bytes(*frame_);
  report.reply_verdict = fmt::format("MBAP transaction {} unit {}", transaction_, request_.slave);
  if (reply_ && !*reply_)
    report.reply_verdict += std::string(", but ") + to_string(reply_->error());
  // Other transactions' frames are only skipped (as another slave's on a serial line); bytes
  // that start no frame are a broken stream.
  if (stream_.bytes_discarded() > discarded_before_) report.rejected_verdict = "not MBAP";
  return report;
}

}  // namespace tiltgate::modbus_rtu
