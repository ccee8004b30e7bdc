#include "serial/shared_wire.h"

#include <algorithm>

namespace tiltgate {
namespace {

// Two transmissions collide when both take time on the line and those times overlap.
bool on_line_together(WireClock::time_point a_from, WireClock::time_point a_until,
                      WireClock::time_point b_from, WireClock::time_point b_until) {
  return a_from < a_until && b_from < b_until && a_from < b_until && b_from < a_until;
}

// What a master reads of a transmission that another drove the line with at the same time:
// every byte broken, so no protocol takes any of it for a frame.
void invert_bytes(std::vector<std::uint8_t>& bytes) {
  for (std::uint8_t& byte : bytes) byte ^= 0xFF;
}

// Once only: inverted twice, a send would arrive whole again.
void break_send(WireSend& send) {
  if (send.broken) return;
  send.broken = true;
  invert_bytes(send.bytes);
}

}  // namespace

SharedWire::SharedWire(std::size_t masters) : held_(std::max<std::size_t>(masters, 1)) {}

bool SharedWire::schedule(WireSend send) {
  // Devices answer at their own times; one that starts talking while another still is (or
  // while a master is) breaks both.
  bool collided = send.starts < written_until_;
  bool met_master = false;
  for (WireSend& other : sends_) {
    if (!on_line_together(other.starts, other.due, send.starts, send.due)) continue;
    collided = true;
    break_send(other);
  }
  for (std::optional<Held>& held : held_) {
    if (!held || !on_line_together(held->from, held->until, send.starts, send.due)) continue;
    collided = met_master = true;
    held->transmission.broken = true;
  }
  if (collided) {
    ++collisions_;
    if (met_master) ++master_collisions_;
    break_send(send);
  }
  const auto at = std::upper_bound(
      sends_.begin(), sends_.end(), send.due,
      [](WireClock::time_point due, const WireSend& queued) { return due < queued.due; });
  const bool first = at == sends_.begin();
  sends_.insert(at, std::move(send));
  return first;
}

WireSend SharedWire::take_next() {
  WireSend next = std::move(sends_.front());
  sends_.pop_front();
  written_until_ = next.due;
  return next;
}

WireClock::time_point SharedWire::transmit(std::size_t master, WireClock::time_point now,
                                           WireClock::duration wire_time,
                                           std::span<const std::uint8_t> bytes, bool heard) {
  std::optional<Held>& mine = held_.at(master);
  if (!mine) mine = Held{now, now, {}};
  // Bytes read while its earlier ones are still crossing follow them on the line.
  const WireClock::time_point from = std::max(now, mine->until);
  const WireClock::time_point until = held_.size() > 1 ? from + wire_time : now;
  mine->until = until;
  MasterTransmission& transmission = mine->transmission;
  transmission.bytes.insert(transmission.bytes.end(), bytes.begin(), bytes.end());
  if (heard) transmission.heard.insert(transmission.heard.end(), bytes.begin(), bytes.end());
  if (held_.size() == 1) return until;

  const bool was_broken = transmission.broken;
  bool collided = false;
  for (std::size_t other = 0; other < held_.size(); ++other) {
    std::optional<Held>& theirs = held_[other];
    if (other == master || !theirs) continue;
    if (!on_line_together(theirs->from, theirs->until, from, until)) continue;
    collided = true;
    theirs->transmission.broken = true;
  }
  for (WireSend& send : sends_) {
    if (!on_line_together(send.starts, send.due, from, until)) continue;
    collided = true;
    break_send(send);
  }
  if (collided) {
    transmission.broken = true;
    if (!was_broken) {
      ++collisions_;
      ++master_collisions_;
    }
  }
  return until;
}

std::optional<MasterTransmission> SharedWire::take_crossed(std::size_t master,
                                                           WireClock::time_point now) {
  std::optional<Held>& mine = held_.at(master);
  if (!mine || mine->until > now) return std::nullopt;
  MasterTransmission crossed = std::move(mine->transmission);
  mine.reset();
  // Inverted only now, so that its bytes read after it collided are broken as well.
  if (crossed.broken) {
    invert_bytes(crossed.bytes);
    crossed.heard.clear();
  }
  return crossed;
}

}  // namespace tiltgate
