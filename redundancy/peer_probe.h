// Asks the other gateway of a redundant pair, over Modbus TCP, whether it is the active one:
// a standby that hears its lines fall silent takes them only when the peer does not answer, or
// answers that it listens too (docs/operations.md, "Warm standby"). One Read Discrete Inputs
// of a unit's input 8 (`standby`, docs/register-maps.md), with a time-out: a peer stopped
// (SIGSTOP) accepts the connection in its kernel but never answers.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <cstdint>
#include <string>

namespace tiltgate {

enum class PeerAnswer : std::uint8_t {
  none,     // no connection, or no reply in time
  standby,  // it listens: its unit's standby input is on
  active,   // it transmits on the unit's line (or answered without saying: taken as active)
};
const char* to_string(PeerAnswer answer);

struct PeerProbe {
  std::string host;
  std::uint16_t port = 0;
  std::uint8_t unit_id = 1;  // a unit on the lines (none configured: only the connection counts)
  bool has_unit = false;
  std::chrono::milliseconds timeout{500};
};

boost::asio::awaitable<PeerAnswer> ask_peer(boost::asio::any_io_executor executor, PeerProbe probe);

}  // namespace tiltgate
