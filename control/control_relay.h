// The gateway's side of a command's framer (control/control_server.h): a ReplyFramer that
// relays what the bus received to the command over the control socket and asks whether the
// reply is whole. The command holds the real framer; this one only carries its answers.
//
// A Line asks a framer synchronously, so the question is asked and answered synchronously
// too, on the socket's descriptor: the command is a local process that answers at once, and a
// command that does not answer within kAnswerWait is taken as gone (every later chunk is
// then refused and the transaction ends in a time-out), so the event loop never waits longer.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string>

#include "driver/line.h"

namespace tiltgate {

class ControlRelayFramer final : public ReplyFramer {
 public:
  explicit ControlRelayFramer(int socket_fd) : fd_(socket_fd) {}

  void reset() override;
  bool feed(std::span<const std::uint8_t> bytes) override;

  // The command stopped answering (or sent something else): the transaction is lost to it.
  bool broken() const { return broken_; }

  static constexpr std::chrono::milliseconds kAnswerWait{100};

 private:
  bool send_line(const std::string& line);

  int fd_;
  bool broken_ = false;
};

}  // namespace tiltgate
