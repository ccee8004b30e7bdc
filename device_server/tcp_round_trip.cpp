// The only file that includes <linux/tcp.h>, whose struct tcp_info has tcpi_min_rtt: glibc's
// <netinet/tcp.h> (which Asio includes) defines an older one under the same name.
#include "device_server/tcp_round_trip.h"

#include <linux/tcp.h>
#include <netinet/in.h>
#include <sys/socket.h>

namespace tiltgate {

std::optional<TcpRoundTrip> read_round_trip(int fd) {
  if (fd < 0) return std::nullopt;
  tcp_info info{};
  socklen_t size = sizeof info;
  if (::getsockopt(fd, IPPROTO_TCP, TCP_INFO, &info, &size) != 0) return std::nullopt;
  // ~0: no sample yet (the handshake gives one on a connection we made).
  const std::uint32_t least = info.tcpi_min_rtt == ~0u ? info.tcpi_rtt : info.tcpi_min_rtt;
  return TcpRoundTrip{.smoothed = std::chrono::microseconds{info.tcpi_rtt},
                      .variation = std::chrono::microseconds{info.tcpi_rttvar},
                      .least = std::chrono::microseconds{least}};
}

}  // namespace tiltgate
