#include "serial/frame_tap.h"

#include <string>

#include "serial/frame_trace.h"
#include "serial/termios_settings.h"

namespace tiltgate {

void FrameTap::request_sent(WallClock::time_point sent_at, std::span<const std::uint8_t> bytes,
                            std::uint8_t address_bytes, bool expects_reply, bool tracing) {
  if (recorder_ != nullptr) {
    recorder_->record(FrameView{sent_at, FrameDirection::to_devices, bytes, address_bytes,
                                expects_reply ? "request" : "request, no reply expected"});
  }
  keep_ = tracing || recorder_ != nullptr;
  received_.clear();
}

void FrameTap::heard(std::span<const std::uint8_t> chunk) {
  if (!keep_ || chunk.empty()) return;
  if (received_.empty()) first_byte_ = WallClock::now();
  received_.insert(received_.end(), chunk.begin(), chunk.end());
}

void FrameTap::reply_taken(const ReplyFramer& framer) {
  if (recorder_ == nullptr || received_.empty()) return;
  // A part after the first began that many characters later on the wire.
  std::size_t offset = 0;
  for (const ReceivedPart& part : reply_parts(received_, framer.report())) {
    const auto later = std::chrono::duration_cast<WallClock::duration>(
        wire_time(offset, baud_, idle_parity(framing_), stop_bits_of(framing_)));
    from_devices(first_byte_ + later, part.bytes, part.verdict);
    offset += part.bytes.size();
  }
}

void FrameTap::reply_lost(const ReplyFramer* framer, std::string_view lost_as) {
  if (recorder_ == nullptr || received_.empty()) return;
  std::string verdict(lost_as);
  if (framer != nullptr) {
    const FramerReport report = framer->report();
    if (!report.rejected_verdict.empty()) verdict += ": " + report.rejected_verdict;
  }
  from_devices(first_byte_, received_, verdict);
}

void FrameTap::collision(std::span<const std::uint8_t> chunk) {
  if (recorder_ != nullptr)
    from_devices(WallClock::now(), chunk, "collision: the echo differs from the request");
}

void FrameTap::late(std::span<const std::uint8_t> chunk, bool starts_burst) {
  if (recorder_ == nullptr) return;
  if (starts_burst) {
    late_done();
    burst_start_ = WallClock::now();
  }
  burst_.insert(burst_.end(), chunk.begin(), chunk.end());
}

void FrameTap::late_done() {
  if (recorder_ != nullptr && !burst_.empty())
    from_devices(burst_start_, burst_, "late: after its request's time-out");
  burst_.clear();
}

void FrameTap::from_devices(WallClock::time_point first_byte, std::span<const std::uint8_t> bytes,
                            std::string_view verdict) {
  recorder_->record(FrameView{first_byte, FrameDirection::from_devices, bytes, 0, verdict});
}

}  // namespace tiltgate
