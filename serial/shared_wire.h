// Who is on a simulated RS485 line, and when: the devices' sends waiting for their time and
// each master's bytes crossing the line, so that two that would be on it at once collide, as
// on a real segment where every transceiver hears every byte. Pure: it is told the times and
// does no I/O (serial/pty_bus_server.h reads and writes the pseudo-terminals).
//
// The rule (README.md, `tiltgate sim ... --second-master`):
// - A device's send is on the line from `starts` to `due` and is written to the masters at
//   `due`, when its last byte has arrived. Two sends that overlap, or one that starts before the
//   last one written was due, collide.
// - A master's bytes are on the line for their wire time from the moment they are read, after
//   its own bytes still crossing it; they are held until their last byte has crossed, and only
//   then reach the devices and the other masters. Bytes of two masters, or of a master and a
//   device, that are on the line at the same time collide.
// - What collides arrives with every byte inverted (XOR 0xFF), which no checksum of the
//   families accepts; a master's broken bytes reach the devices as noise that they cannot
//   answer. Each transmission that joins the line while another is on it, or stretches over
//   one, counts one collision, once.
// - A line with one master keeps the older rule: its bytes are not held and never collide
//   (only the devices' sends collide with each other).
#pragma once

#include <chrono>
#include <cstdint>
#include <deque>
#include <optional>
#include <span>
#include <vector>

namespace tiltgate {

using WireClock = std::chrono::steady_clock;

struct WireSend {
  WireClock::time_point starts{};  // when its first byte would be on the line
  WireClock::time_point due{};     // when its last byte has arrived: it is written then
  std::vector<std::uint8_t> bytes{};
  bool broken = false;  // it collided: its bytes are inverted (once)
};

// A master's bytes once their last byte has crossed the line.
struct MasterTransmission {
  std::vector<std::uint8_t> bytes{};  // everything it wrote, for the other masters
  std::vector<std::uint8_t> heard{};  // what the devices could hear (sent at their baud)
  bool broken = false;  // it collided: every byte of `bytes` is inverted, `heard` is empty
};

class SharedWire {
 public:
  explicit SharedWire(std::size_t masters);

  // Queues a device's send by its due time, broken (with what it meets) when it collides.
  // True when it is now the first one due.
  bool schedule(WireSend send);
  bool has_sends() const { return !sends_.empty(); }
  WireClock::time_point next_due() const { return sends_.front().due; }
  // The first send, taken off the queue to be written.
  WireSend take_next();
  // Forgets the sends not yet written (no master is there to hear them).
  void drop_sends() { sends_.clear(); }

  // `bytes` read from `master` at `now`, on the line for `wire_time` after its own earlier
  // bytes; `heard`: whether the devices can hear them. Returns when they have crossed the
  // line: `now` on a line with one master, whose bytes are never held.
  WireClock::time_point transmit(std::size_t master, WireClock::time_point now,
                                 WireClock::duration wire_time, std::span<const std::uint8_t> bytes,
                                 bool heard);
  // What `master` sent, taken to be delivered once its last byte has crossed the line by
  // `now`; nullopt when it sent nothing since, or is still sending.
  std::optional<MasterTransmission> take_crossed(std::size_t master, WireClock::time_point now);
  // Forgets what `master` was transmitting (its adapter is gone).
  void drop_transmission(std::size_t master) { held_.at(master).reset(); }

  // Transmissions that collided (devices' sends and masters' bytes).
  std::uint64_t collisions() const { return collisions_; }
  // Those of them that a master's bytes were in.
  std::uint64_t master_collisions() const { return master_collisions_; }

 private:
  struct Held {
    WireClock::time_point from{};
    WireClock::time_point until{};
    MasterTransmission transmission{};
  };
  std::deque<WireSend> sends_;  // by due time
  WireClock::time_point written_until_{};  // the due time of the last send written
  std::vector<std::optional<Held>> held_;  // per master: its bytes still crossing the line
  std::uint64_t collisions_ = 0;
  std::uint64_t master_collisions_ = 0;
};

}  // namespace tiltgate
