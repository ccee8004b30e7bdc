// The passive decoder (capture/passive_decoder.h) with each protocol's passive framer: the
// input's second byte picks the protocol, the rest is a line heard in random-sized reads with
// random gaps (some longer than the silence, some longer than the reply window). Whatever it
// hears, every byte must come out in exactly one frame, the frames in wire order, numbered in
// that order, and each reply paired with the request handed on just before it.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "capture/passive_decoder.h"
#include "fuzz/chunks.h"
#include "modbus_rtu/passive_framer.h"
#include "rieker/passive_framer.h"
#include "spectron/passive_framers.h"

using namespace tiltgate;
using tiltgate::fuzz::check;

namespace {

constexpr PassiveFramer kFramers[] = {rieker::passive_frame, modbus_rtu::passive_frame,
                                      spectron::ascii_passive_frame,
                                      spectron::nine_bit_passive_frame};

class CheckingSink final : public HeardTrafficSink {
 public:
  void on_frame(const HeardFrame& frame) override {
    check(frame.number > last_number_);
    check(!frame.frame.bytes.empty());
    last_number_ = frame.number;
    if (frame.kind == HeardKind::request) last_request_ = frame.number;
    if (frame.answers) check(*frame.answers == last_request_);
    heard.insert(heard.end(), frame.frame.bytes.begin(), frame.frame.bytes.end());
  }
  void on_exchange(const HeardExchange& exchange) override {
    check(exchange.request.kind == HeardKind::request);
    if (exchange.reply) check(exchange.reply->answers == exchange.request.number);
  }
  std::vector<std::uint8_t> heard;

 private:
  std::uint64_t last_number_ = 0;
  std::uint64_t last_request_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const PassiveFramer framer = kFramers[data[1] % std::size(kFramers)];
  std::vector<std::uint8_t> input(data, data + size);
  input.erase(input.begin() + 1);  // the protocol's byte is not heard
  tiltgate::fuzz::Chunks reads(input);

  CheckingSink sink;
  PassiveDecoderOptions options;
  options.framer = framer;
  options.character_time = std::chrono::microseconds(80);
  options.reply_window = std::chrono::milliseconds(50);
  PassiveDecoder decoder(options, sink);
  auto now = std::chrono::steady_clock::time_point{} + std::chrono::hours(1);
  while (!reads.done()) {
    const auto piece = reads.next();
    // Back to back, or after a pause up to 3 * 31 ms: past the silence, or the reply window.
    now += std::chrono::milliseconds(3 * (piece[0] % 32 > 20 ? piece[0] % 32 : 0));
    decoder.heard(piece, now);
    now += piece.size() * options.character_time;
    if (piece[0] % 7 == 0) decoder.advance(now);
  }
  decoder.finish();
  check(sink.heard == std::vector<std::uint8_t>(reads.stream().begin(), reads.stream().end()));
  return 0;
}
