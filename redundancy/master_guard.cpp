#include "redundancy/master_guard.h"

#include <fmt/format.h>

#include <vector>

#include "capture/passive_decoder.h"
#include "driver/hex.h"

namespace tiltgate {

namespace {

// Collects the intact requests a decoder cut from the bytes.
class RequestsHeard final : public HeardTrafficSink {
 public:
  void on_frame(const HeardFrame& frame) override {
    if (frame.kind == HeardKind::request && frame.intact && first.empty()) first = frame.frame.bytes;
    if (frame.kind == HeardKind::request && frame.intact) ++count;
  }
  void on_exchange(const HeardExchange&) override {}
  std::vector<std::uint8_t> first;
  std::size_t count = 0;
};

}  // namespace

MasterGuard::MasterGuard(std::string bus, PassiveFramer framer,
                         std::chrono::nanoseconds character_time, StandDown stand_down)
    : bus_(std::move(bus)),
      framer_(framer),
      character_time_(character_time),
      stand_down_(std::move(stand_down)) {}

void MasterGuard::arm(Clock::time_point now) {
  held_ = false;
  alive_ = now;
}

void MasterGuard::stand_down(std::string why) {
  held_ = true;
  if (stand_down_) stand_down_(std::move(why));
}

bool MasterGuard::may_send(std::span<const std::uint8_t> received) {
  if (held_) return false;
  const auto now = Clock::now();
  const auto stalled = std::chrono::duration_cast<std::chrono::milliseconds>(now - alive_);
  if (stalled > stall_limit_) {
    stand_down(fmt::format("this gateway was held up for {} ms (stopped, or starved of CPU): the "
                           "standby may have taken the lines meanwhile",
                           stalled.count()));
    return false;
  }
  if (received.empty() || framer_ == nullptr) return true;
  RequestsHeard heard;
  PassiveDecoderOptions options;
  options.framer = framer_;
  options.character_time = character_time_;
  options.steady_anchor = now;
  options.wall_anchor = std::chrono::system_clock::now();
  PassiveDecoder decoder(options, heard);
  decoder.heard(received, now - character_time_ * received.size());
  decoder.finish();
  if (heard.count == 0) return true;
  stand_down(fmt::format("{}: another master's request heard on the line ({}): two masters on "
                         "one line collide",
                         bus_, hex_bytes(heard.first)));
  return false;
}

}  // namespace tiltgate
