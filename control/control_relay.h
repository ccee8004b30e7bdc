// The gateway's side of a command's framer (control/control_server.h): a ReplyFramer that
// relays what the bus received to the command over the control socket and asks whether the
// reply is whole. The command holds the real framer; this one only carries its answers.
//
// The question is asked asynchronously (asks_asynchronously(): the Line awaits feed_async()),
// on the socket the session owns, with Asio on the buses' executor: while the command thinks,
// every other bus goes on. A command that does not answer within kAnswerWait is taken as gone
// (every later chunk is then refused and the transaction ends in a time-out). reset() sends
// its line without waiting at all: the socket is idle then (the command reads each line the
// moment it comes), and one that cannot take a line at once is as gone as a silent command.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/local/stream_protocol.hpp>
#include <boost/asio/streambuf.hpp>
#include <chrono>
#include <cstdint>
#include <span>

#include "driver/line.h"

namespace tiltgate {

class ControlRelayFramer final : public ReplyFramer {
 public:
  // The session's socket and its input buffer, lent for the exchange: the session awaits the
  // exchange meanwhile, and reads on from what the relay leaves in `input`.
  ControlRelayFramer(boost::asio::local::stream_protocol::socket& socket,
                     boost::asio::streambuf& input)
      : socket_(socket), input_(input) {}

  void reset() override;
  // Not asked so: a Line asks this framer asynchronously, and a synchronous question could
  // only be answered by waiting. The command is then taken as gone.
  bool feed(std::span<const std::uint8_t> bytes) override;
  bool asks_asynchronously() const override { return true; }
  boost::asio::awaitable<bool> feed_async(std::span<const std::uint8_t> bytes) override;

  // The command stopped answering (or sent something else): the transaction is lost to it.
  bool broken() const { return broken_; }
  // What the line received in the latest attempt as the reply, for the audit trail
  // (control/carried_change.h): the command's framer took it whole; its checksum is the
  // command's to judge.
  FramerReport report() const override { return FramerReport{received_, "", ""}; }

  static constexpr std::chrono::milliseconds kAnswerWait{100};

 private:
  boost::asio::local::stream_protocol::socket& socket_;
  boost::asio::streambuf& input_;
  bool broken_ = false;
  std::vector<std::uint8_t> received_;
};

}  // namespace tiltgate
