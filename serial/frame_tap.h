// What a SerialLine tells its frame recorder (driver/captured_frame.h: the bus's black box),
// and the bytes of the current attempt, which the trace log shows too (serial/frame_trace.h).
// The line calls it at each step of a transaction: the request written, the bytes of the reply
// as they come, the reply taken or lost, an echo that collided, late bursts. Each frame goes to
// the recorder as views of the buffers kept here, reused from one attempt to the next: a frame
// costs the recorder's one copy, no allocation of the line's own once the buffers have grown.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "driver/captured_frame.h"
#include "driver/framing.h"
#include "driver/line.h"

namespace tiltgate {

class FrameTap {
 public:
  using WallClock = std::chrono::system_clock;

  // `baud` and `framing`: the line's, for the wire time between a reply's parts.
  FrameTap(std::uint32_t baud, Framing framing) : baud_(baud), framing_(framing) {}

  // Null stops recording; the recorder must outlive the line.
  void record_to(FrameRecorder* recorder) { recorder_ = recorder; }
  // How long the recorder keeps frames (0: no recorder).
  std::chrono::seconds kept() const {
    return recorder_ != nullptr ? recorder_->keep() : std::chrono::seconds{0};
  }

  // A request was handed to the port at `sent_at`; the attempt's bytes start afresh, and are
  // kept if recording or `tracing`.
  void request_sent(WallClock::time_point sent_at, std::span<const std::uint8_t> bytes,
                    std::uint8_t address_bytes, bool expects_reply, bool tracing);
  // Bytes of the attempt's reply, as read (an echo taken off).
  void heard(std::span<const std::uint8_t> chunk);
  // What the attempt received so far (kept only if recording or tracing).
  std::span<const std::uint8_t> heard_bytes() const { return received_; }
  // The framer took a reply: its parts recorded (bytes before it, the reply, bytes after).
  void reply_taken(const ReplyFramer& framer);
  // The attempt ended without a reply: what it received, as `lost_as` ("no reply") and the
  // framer's account of the bytes.
  void reply_lost(const ReplyFramer* framer, std::string_view lost_as);
  // Received bytes that were not the echo of the request: another transmitter collided.
  void collision(std::span<const std::uint8_t> chunk);
  // Bytes after a time-out; `starts_burst`: after a quiet gap, the first of a new late reply.
  void late(std::span<const std::uint8_t> chunk, bool starts_burst);
  // The late-reply window closed: the burst being received is recorded.
  void late_done();

 private:
  void from_devices(WallClock::time_point first_byte, std::span<const std::uint8_t> bytes,
                    std::string_view verdict);

  std::uint32_t baud_;
  Framing framing_;
  FrameRecorder* recorder_ = nullptr;
  bool keep_ = false;  // this attempt's bytes are kept
  std::vector<std::uint8_t> received_;
  WallClock::time_point first_byte_{};
  std::vector<std::uint8_t> burst_;  // the late burst being received
  WallClock::time_point burst_start_{};
};

}  // namespace tiltgate
