// The tightest blocking Rieker master, as a vendor's example program would poll a bus: the
// reference bench/bus_gateway.py holds `tiltgate run` against on the same simulated bus.
//
// One thread, no event loop: write the Get Angle request the gateway's driver sends for an H6
// (type 4, X and Y in one reply: docs/protocols.md, "Rieker verified frames"), read exactly the
// 17 bytes of its reply with blocking read() calls, check it, and go on to the next address,
// round robin, for a fixed time. poll() bounds each wait for a reply, so a lost one counts as a
// time-out instead of hanging the program. No gap is left between the reply and the next
// request: at 125000 baud the 17-byte reply itself outlasts the manual's 1 ms between master
// packets (docs/protocols.md, "Packet timing"), which the gateway leaves from the end of its
// request. Prints one line of key=value fields.
//
// Usage: bench_tight_master PORT BAUD SECONDS ADDRESSES   (ADDRESSES: "1-10", or "1,5,7-9")
#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "rieker/codec.h"
#include "serial/termios_settings.h"

using namespace tiltgate;
using namespace std::chrono;

namespace {

// The gateway's default reply time-out (`timeout_ms` of the [[bus]], docs/configuration.md).
constexpr int kReplyTimeoutMs = 50;
// Get Angle type 4's reply: the header, two floats, the CRC.
constexpr std::size_t kAngleReplySize = rieker::kMinFrameSize + 8;

// "1-10" or "1,5,7-9"; empty on anything else.
std::vector<std::uint16_t> parse_addresses(const std::string& text) {
  std::vector<std::uint16_t> addresses;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos
                                                                           : comma - start);
    unsigned first = 0, last = 0;
    char tail = 0;
    if (std::sscanf(item.c_str(), "%u-%u%c", &first, &last, &tail) == 2) {
    } else if (std::sscanf(item.c_str(), "%u%c", &first, &tail) == 1) {
      last = first;
    } else {
      return {};
    }
    if (first < rieker::kMinSensorAddress || last > rieker::kMaxSensorAddress || first > last)
      return {};
    for (unsigned a = first; a <= last; ++a) addresses.push_back(static_cast<std::uint16_t>(a));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return addresses;
}

// Reads exactly `size` bytes, each wait bounded by what is left of the reply time-out.
// False on a time-out or a read error.
bool read_exactly(int fd, std::uint8_t* buffer, std::size_t size) {
  const auto deadline = steady_clock::now() + milliseconds(kReplyTimeoutMs);
  std::size_t have = 0;
  while (have < size) {
    const auto left = duration_cast<milliseconds>(deadline - steady_clock::now()).count();
    pollfd waiting{fd, POLLIN, 0};
    if (left < 0 || ::poll(&waiting, 1, static_cast<int>(left) + 1) <= 0) return false;
    const ssize_t got = ::read(fd, buffer + have, size - have);
    if (got <= 0) return false;
    have += static_cast<std::size_t>(got);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: %s PORT BAUD SECONDS ADDRESSES (e.g. 1-10)\n", argv[0]);
    return 2;
  }
  const char* port = argv[1];
  const auto baud = static_cast<std::uint32_t>(std::strtoul(argv[2], nullptr, 10));
  const double run_seconds = std::strtod(argv[3], nullptr);
  const std::vector<std::uint16_t> addresses = parse_addresses(argv[4]);
  if (baud == 0 || run_seconds <= 0 || addresses.empty()) {
    std::fprintf(stderr, "%s: bad BAUD, SECONDS or ADDRESSES\n", argv[0]);
    return 2;
  }

  const int fd = ::open(port, O_RDWR | O_NOCTTY);
  if (fd < 0) {
    std::fprintf(stderr, "%s: %s: %s\n", argv[0], port, std::strerror(errno));
    return 1;
  }
  // Raw 8N1 at the given rate, set as the gateway sets it (termios2, since 125000 has no
  // B-constant for cfsetspeed). A pseudo-terminal ignores the rate: the simulator paces.
  if (auto raw = apply_raw_settings(fd, baud, Parity::none); !raw) {
    std::fprintf(stderr, "%s: %s: %s\n", argv[0], port, raw.error().message().c_str());
    return 1;
  }

  // The requests, encoded once: a vendor's example would keep them as constant byte arrays.
  std::vector<rieker::Frame> requests;
  std::vector<std::vector<std::uint8_t>> encoded;
  for (std::uint16_t address : addresses) {
    requests.push_back(*rieker::get_angle_request(rieker::Route{address, 0},
                                                  rieker::AngleType::x_and_y));
    encoded.push_back(rieker::encode(requests.back()));
  }

  std::uint64_t polls = 0, timeouts = 0, bad_replies = 0;
  std::uint8_t reply[kAngleReplySize];
  const auto start = steady_clock::now();
  const auto end = start + duration_cast<steady_clock::duration>(duration<double>(run_seconds));
  for (std::size_t next = 0; steady_clock::now() < end; next = (next + 1) % requests.size()) {
    const std::vector<std::uint8_t>& request = encoded[next];
    if (::write(fd, request.data(), request.size()) != static_cast<ssize_t>(request.size())) {
      std::fprintf(stderr, "%s: write: %s\n", argv[0], std::strerror(errno));
      return 1;
    }
    if (!read_exactly(fd, reply, sizeof reply)) {
      ++timeouts;
      discard_input(fd);  // a late reply must not be read as the next one's
      continue;
    }
    auto frame = rieker::decode(reply);
    if (!frame || !rieker::is_reply_to(*frame, requests[next]) ||
        !rieker::parse_angle_reply(*frame, rieker::AngleType::x_and_y)) {
      ++bad_replies;
      discard_input(fd);
      continue;
    }
    ++polls;
  }
  const double elapsed = duration<double>(steady_clock::now() - start).count();
  ::close(fd);
  std::printf("polls=%llu polls_per_s=%.1f timeouts=%llu bad_replies=%llu seconds=%.3f\n",
              static_cast<unsigned long long>(polls), polls / elapsed,
              static_cast<unsigned long long>(timeouts),
              static_cast<unsigned long long>(bad_replies), elapsed);
  return 0;
}
