// A PLC as the plant runs one, for end-to-end tests of a shared line: on a thread of its own it
// reads every unit's status word and age (input registers 6 and 7) and its angle_x (input
// registers 0-1) back to back, one cycle every `cycle`, and keeps, per unit, what a PLC would
// have seen go wrong: a status without bit 0 (online) or with bit 1 (stale), an angle answered
// with an exception (0x0B: unavailable), and the oldest reading. The oldest reading comes from
// the age register: each reading's time is the read's time less its age, and the longest gap
// between two readings seen one after the other is how old the first got before the next came
// (what a missed reading adds makes it longer, never shorter).
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "e2e/support/modbus_client.h"

namespace tiltgate::test {

struct UnitSeen {
  int reads = 0;
  int offline = 0;      // status bit 0 clear
  int stale = 0;        // status bit 1 set
  int unavailable = 0;  // the angle answered an exception (or nothing)
  int last_exception = 0;
  // The longest a reading went without a newer one, in ms, as the age register shows it.
  std::int64_t worst_age_ms = 0;
  // The angle_x values read (a reply taken for another sensor's would show here).
  float angle_min = INFINITY;
  float angle_max = -INFINITY;
};

class PlcWatch {
 public:
  using Clock = std::chrono::steady_clock;

  PlcWatch(std::uint16_t port, std::vector<int> units,
           std::chrono::milliseconds cycle = std::chrono::milliseconds(30))
      : port_(port), units_(std::move(units)), cycle_(cycle) {
    for (int unit : units_) seen_[unit];
    thread_ = std::thread([this] { watch(); });
  }
  ~PlcWatch() { stop(); }
  PlcWatch(const PlcWatch&) = delete;
  PlcWatch& operator=(const PlcWatch&) = delete;

  void stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }
  // What was seen of `unit` so far.
  UnitSeen seen(int unit) const {
    std::lock_guard lock(mutex_);
    return seen_.at(unit).seen;
  }
  // The first time `unit` read as not online (status bit 0 clear), if it did.
  std::optional<Clock::time_point> first_offline(int unit) const {
    std::lock_guard lock(mutex_);
    return seen_.at(unit).first_offline;
  }
  // The first time at or after `since` that `unit`'s angle answered an exception (or nothing).
  std::optional<Clock::time_point> first_unavailable_since(int unit, Clock::time_point since) const {
    std::lock_guard lock(mutex_);
    for (const Clock::time_point at : seen_.at(unit).unavailable_at)
      if (at >= since) return at;
    return std::nullopt;
  }
  // The first time at or after `since` that every one of `units` read online and not stale
  // with its angle readable and a reading newer than `since`.
  std::optional<Clock::time_point> all_fresh_since(Clock::time_point since) const {
    std::lock_guard lock(mutex_);
    std::optional<Clock::time_point> latest;
    for (const auto& [unit, track] : seen_) {
      auto at = std::find_if(track.fresh.begin(), track.fresh.end(),
                             [&](const Fresh& f) { return f.read_at >= since && f.taken > since; });
      if (at == track.fresh.end()) return std::nullopt;
      latest = std::max(latest.value_or(at->read_at), at->read_at);
    }
    return latest;
  }

 private:
  struct Fresh {
    Clock::time_point read_at;
    Clock::time_point taken;  // the reading's time: read_at less its age
  };
  struct Track {
    UnitSeen seen;
    std::optional<Clock::time_point> last_taken;
    std::optional<Clock::time_point> first_offline;
    std::vector<Clock::time_point> unavailable_at;  // every read whose angle was unavailable
    std::vector<Fresh> fresh;  // every read that found the unit fresh
  };

  void watch() {
    ModbusClient client(port_, units_.front());
    while (running_) {
      const auto cycle_start = Clock::now();
      for (int unit : units_) read_unit(client, unit);
      std::this_thread::sleep_until(cycle_start + cycle_);
    }
  }

  void read_unit(ModbusClient& client, int unit) {
    client.unit(unit);
    const std::vector<std::uint16_t> status = client.input(6, 2);
    const auto read_at = Clock::now();
    const std::vector<std::uint16_t> angle = client.input(0, 2);
    const int exception = angle.empty() ? client.exception() : 0;
    std::lock_guard lock(mutex_);
    Track& track = seen_[unit];
    ++track.seen.reads;
    if (angle.empty()) {
      ++track.seen.unavailable;
      track.seen.last_exception = exception;
      track.unavailable_at.push_back(Clock::now());
    } else {
      const float x = modbus_get_float_abcd(angle.data());
      track.seen.angle_min = std::min(track.seen.angle_min, x);
      track.seen.angle_max = std::max(track.seen.angle_max, x);
    }
    if (status.size() != 2) return;
    const bool online = (status[0] & 0x01) != 0;
    const bool stale = (status[0] & 0x02) != 0;
    if (!online) {
      ++track.seen.offline;
      if (!track.first_offline) track.first_offline = read_at;
    }
    if (stale) ++track.seen.stale;
    if (status[1] == 65535) return;  // no reading yet, or one older than the register holds
    const auto taken = read_at - std::chrono::milliseconds(status[1]);
    // A reading is the same one read again when its time moved by less than a read's rounding.
    if (track.last_taken && taken - *track.last_taken > std::chrono::milliseconds(5)) {
      const auto gap = std::chrono::duration_cast<std::chrono::milliseconds>(taken - *track.last_taken);
      track.seen.worst_age_ms = std::max<std::int64_t>(track.seen.worst_age_ms, gap.count());
    }
    if (!track.last_taken || taken > *track.last_taken) track.last_taken = taken;
    // The age so far of the reading held now counts too (a sensor that never reads again).
    track.seen.worst_age_ms = std::max<std::int64_t>(track.seen.worst_age_ms, status[1]);
    if (online && !stale && !angle.empty()) track.fresh.push_back({read_at, taken});
  }

  std::uint16_t port_;
  std::vector<int> units_;
  std::chrono::milliseconds cycle_;
  std::atomic<bool> running_{true};
  mutable std::mutex mutex_;
  std::map<int, Track> seen_;
  std::thread thread_;
};

}  // namespace tiltgate::test
