// What a bus's sensor pollers read instead of the line while the gateway is the standby of a
// redundant pair (docs/operations.md, "Warm standby"): the active master's exchanges, heard on
// the line (redundancy/heard_exchanges.h). BusScheduler::listen_to().
#pragma once

#include <boost/asio/awaitable.hpp>
#include <memory>

#include "driver/line.h"

namespace tiltgate {

class HeardSource {
 public:
  virtual ~HeardSource() = default;
  // A Line for one sensor's poller: it answers each request with what the same request got
  // when the active master sent it, and sends nothing.
  virtual std::unique_ptr<Line> line_for_poller() = 0;
  // After a poll on `line` (one of line_for_poller()'s): returns at once when the poll took
  // something heard; else when a request not heard before is heard, or after a second, so a
  // poller whose requests nobody asks yet does not spin.
  virtual boost::asio::awaitable<void> pace(Line& line) = 0;
};

}  // namespace tiltgate
