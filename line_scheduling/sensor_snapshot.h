// What the Modbus TCP threads read of a sensor: a copy of its state, its derived values and its
// written registers, made on the bus's thread after every change and never modified after.
// A reply built from one snapshot is consistent (no poll lands halfway through it), and no
// lock is held while it is built.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <vector>

#include "driver/sensor_state.h"
#include "line_scheduling/sensor_processing.h"

namespace tiltgate {

struct SensorSnapshot {
  SensorState state;
  DerivedState derived;
  std::vector<std::uint16_t> written;
};

// The latest snapshot: the bus's thread replaces it, any thread takes it. One lock for every
// slot, so a reader can take many sensors' snapshots at one instant (an aggregate's reply). It
// guards pointer copies only, never I/O or a copy of the state; a replaced snapshot lives on
// with whoever still reads it.
class SnapshotSlot {
 public:
  // Held while taking several slots' snapshots: nothing is published meanwhile.
  class Instant {
   public:
    Instant() : lock_(mutex()) {}

   private:
    std::shared_lock<std::shared_mutex> lock_;
  };

  SnapshotSlot() = default;
  // Only while nobody else uses the slot (a sensor being built and returned).
  SnapshotSlot(SnapshotSlot&& other) noexcept
      : current_(other.get()), generation_(other.generation()) {}

  void publish(std::shared_ptr<const SensorSnapshot> next) {
    {
      std::unique_lock lock(mutex());
      current_.swap(next);
      generation_.fetch_add(1, std::memory_order_release);
    }
    // `next` now holds the old snapshot: freed here, outside the lock, when nobody reads it.
  }
  // Goes up with every publish(): a reader that keeps a snapshot (a connection's, see
  // gateway/router_reader.h) takes a new one only when this moved, so a read of an unchanged
  // sensor takes no lock and touches no reference count another thread touches too. Read
  // before get(): the snapshot got is then at least that new.
  std::uint64_t generation() const { return generation_.load(std::memory_order_acquire); }
  std::shared_ptr<const SensorSnapshot> get() const {
    std::shared_lock lock(mutex());
    return current_;
  }
  std::shared_ptr<const SensorSnapshot> get(const Instant&) const { return current_; }

 private:
  static std::shared_mutex& mutex() {
    static std::shared_mutex every_slot;
    return every_slot;
  }

  std::shared_ptr<const SensorSnapshot> current_;
  std::atomic<std::uint64_t> generation_ = 0;
};

}  // namespace tiltgate
