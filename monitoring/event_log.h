// The event record (docs/monitoring.md, "Events"): every event of the monitoring, kept on disk
// in <state_dir>/events with the store (store/record_store.h: a CRC per record, a torn write
// loses at most the last one), bounded, across restarts and power cuts, and the newest of
// them in memory for `GET /api/events`, the console and the MQTT topic.
//
// Bound: at most kEventStoreBytes on disk (the oldest dropped first, whole segments), the
// newest kEventsInMemory in memory. Durability: append() writes each event at once (a crash of
// the process loses nothing); sync() (the owner's, after each batch) makes them survive a
// power cut. A disk that refuses keeps the log going in memory, and says so (fault()).
//
// Threads: any (one mutex). The monitoring's own thread appends; the HTTP threads query.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "monitoring/event_record.h"
#include "store/record_store.h"

namespace tiltgate::monitoring {

inline constexpr std::uint64_t kEventStoreBytes = 8ull * 1024 * 1024;
inline constexpr std::uint64_t kEventSegmentBytes = 512ull * 1024;
inline constexpr std::size_t kEventsInMemory = 10000;

// What `GET /api/events` asks for: all of them match what is given.
struct EventQuery {
  std::string sensor;                 // empty: every sensor
  std::string kind;                   // empty: every kind
  std::optional<std::int64_t> since;  // unix_ms, inclusive
  std::optional<std::int64_t> until;  // unix_ms, exclusive
  std::size_t limit = 100;
};

class EventLog {
 public:
  // Opens (or creates) the log in `dir` and reads the newest events back; without a directory
  // (empty path) or when it cannot be opened, the log is kept in memory (fault() says why).
  explicit EventLog(const std::filesystem::path& dir);

  // Numbers the event (seq), keeps it and returns it as kept.
  EventRecord append(EventRecord event);
  // Syncs what was appended since the last sync to the disk.
  void sync();
  // Newest first, at most query.limit of them, from those in memory.
  std::vector<EventRecord> recent(const EventQuery& query) const;
  // Those after `seq` (seq 0: every one in memory), oldest first, at most `max`.
  std::vector<EventRecord> after(std::uint64_t seq, std::size_t max) const;
  // The seq the last event took; 0 before the first.
  std::uint64_t last_seq() const;

  std::uint64_t appended() const;  // since start
  std::optional<std::string> fault() const;
  // Lines for the log: what opening repaired, and each time the disk refused or took again.
  std::vector<std::string> take_notices();

 private:
  mutable std::mutex mutex_;
  std::optional<store::RecordStore> store_;
  std::deque<EventRecord> memory_;  // oldest first
  std::uint64_t next_seq_ = 1;
  std::uint64_t appended_ = 0;
  std::optional<std::string> fault_;
  std::vector<std::string> notices_;
};

}  // namespace tiltgate::monitoring
