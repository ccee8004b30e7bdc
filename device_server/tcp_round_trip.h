// The kernel's own measure of a TCP connection's round trip (TCP_INFO), which a line on a
// device server adds to its reply waits (device_server/network_port.h).
#pragma once

#include <chrono>
#include <optional>

namespace tiltgate {

struct TcpRoundTrip {
  std::chrono::microseconds smoothed{0};   // srtt
  std::chrono::microseconds variation{0};  // rttvar
  std::chrono::microseconds least{0};      // the least seen on the connection
};

// Nothing when `fd` is no TCP socket.
std::optional<TcpRoundTrip> read_round_trip(int fd);

}  // namespace tiltgate
