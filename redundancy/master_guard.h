// What keeps an active gateway of a redundant pair from transmitting over another master
// (docs/operations.md, "Warm standby"). Its line shows it what arrived since its last exchange
// before each request (SerialLine::check_before_sending): a request among those bytes, cut by
// the protocol's passive framer with its checksum intact, was sent by someone else, since this
// gateway's own were answered or timed out before. The request is then kept back and the
// gateway told to stand down; so is every request after a stall of the gateway's own (it was
// stopped or starved for longer than half the takeover time, long enough for the standby to
// take over meanwhile), until the gateway has listened again.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "driver/passive_framing.h"

namespace tiltgate {

class MasterGuard {
 public:
  using Clock = std::chrono::steady_clock;
  // Called once per stand-down, with why, on the line's thread.
  using StandDown = std::function<void(std::string why)>;

  MasterGuard(std::string bus, PassiveFramer framer, std::chrono::nanoseconds character_time,
              StandDown stand_down);

  // The line's send check: whether the request may go out now.
  bool may_send(std::span<const std::uint8_t> received);
  // The gateway is alive now (its event loop ran): called every tick of the controller.
  void alive(Clock::time_point now) { alive_ = now; }
  // A stall longer than this keeps requests back.
  void set_stall_limit(std::chrono::milliseconds limit) { stall_limit_ = limit; }
  // Sending is allowed (the gateway took the line), or not (it stood down).
  void arm(Clock::time_point now);
  void hold() { held_ = true; }
  bool held() const { return held_; }

 private:
  void stand_down(std::string why);

  std::string bus_;
  PassiveFramer framer_;
  std::chrono::nanoseconds character_time_;
  StandDown stand_down_;
  Clock::time_point alive_{};
  std::chrono::milliseconds stall_limit_{1000};
  bool held_ = true;
};

}  // namespace tiltgate
