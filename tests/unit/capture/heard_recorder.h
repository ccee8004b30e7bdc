// What a passive decoder handed on, kept for a test to look at: every frame in the order it
// came, and every exchange.
#pragma once

#include <string>
#include <vector>

#include "capture/passive_decoder.h"

namespace tiltgate::test {

class HeardRecorder final : public HeardTrafficSink {
 public:
  void on_frame(const HeardFrame& frame) override { frames.push_back(frame); }
  void on_exchange(const HeardExchange& exchange) override { exchanges.push_back(exchange); }

  std::vector<std::string> verdicts() const {
    std::vector<std::string> out;
    for (const HeardFrame& frame : frames) out.push_back(frame.frame.verdict);
    return out;
  }

  std::vector<HeardFrame> frames;
  std::vector<HeardExchange> exchanges;
};

}  // namespace tiltgate::test
