// The audit trail (docs/operations.md, "The audit trail"): every change made through any door
// (Modbus, Sparkplug, the control socket, the console) as one AuditRecord, kept in
// <state_dir>/audit/ with the store (store/record_store.h: a CRC per record, a torn write
// loses at most the last one), across restarts, and written to the journal as "audit: ...".
//
// One gateway per folder: it is locked (flock on its `lock` file) while the trail keeps it; a
// second gateway on the same state_dir keeps its trail in memory, and says so.
//
// Bound: the newest max_records in memory (what recent() searches), and at most
// kAuditStoreBytes on disk, the oldest dropped first (whole segments of kAuditSegmentBytes).
// Each record is fsynced as it is written: changes are rare, and a power cut right after one
// must not lose it.
//
// Threads: any (one mutex). Owned by the composition root (app/served_gateway.h), which gives
// the gateway a reference to it; no global.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "audit/audit_counts.h"
#include "audit/audit_record.h"
#include "store/record_store.h"

namespace tiltgate {

inline constexpr std::size_t kAuditMaxRecords = 10000;
inline constexpr std::uint64_t kAuditStoreBytes = 4ull * 1024 * 1024;
inline constexpr std::uint64_t kAuditSegmentBytes = 256ull * 1024;

class AuditTrail {
 public:
  // state_dir empty: kept in memory only (tiltgate demo). An unusable folder: logged, memory
  // only.
  explicit AuditTrail(std::string state_dir, std::size_t max_records = kAuditMaxRecords);
  AuditTrail(const AuditTrail&) = delete;
  AuditTrail& operator=(const AuditTrail&) = delete;

  // Keeps the trail in <state_dir>/audit/ from now on (the composition root calls it once the
  // gateway serves as its own user, so the files are that user's): the records found there
  // come first, then those recorded in memory meanwhile, which are written there too.
  void open(const std::string& state_dir);

  // Any thread; stamps the time when the record has none. Also logged: "audit: ...".
  void record(AuditRecord record);

  // Empty fields match every record; `who` matches a part ("10.0.0.5" finds its connections),
  // the others the whole field. limit 0: no limit.
  struct Filter {
    std::string door, sensor, who, setting;
    std::int64_t since_ms = 0;
    std::size_t limit = 200;
  };
  std::vector<AuditRecord> recent(const Filter& filter) const;  // newest first, any thread
  // Recorded since the gateway started (not those found on disk), by door and result class.
  AuditCounts counts() const;
  // Where the trail is kept; empty while in memory only.
  std::string folder() const;

 private:
  void keep(AuditRecord record);  // in memory, within max_records_
  void store_record(const AuditRecord& record);
  void log_store_notices();

  mutable std::mutex mutex_;
  std::size_t max_records_;
  std::deque<AuditRecord> records_;  // oldest first
  store::UniqueFd lock_;  // before the store: released after it closed
  std::optional<store::RecordStore> store_;
  std::map<std::pair<std::string, std::string>, std::uint64_t> counts_;  // (door, class)
};

// The folder the trail keeps in, under a state_dir: <state_dir>/audit.
std::string audit_folder(const std::string& state_dir);
// Every record a trail keeps in `folder`, oldest first, read without opening it (safe beside a
// running gateway: store/record_reader.h). Records that are not audit records are skipped.
Expected<std::vector<AuditRecord>, std::string> read_audit_folder(const std::string& folder);
// The records of `all` (oldest first) that `filter` selects, newest first.
std::vector<AuditRecord> select_audit(const std::deque<AuditRecord>& all,
                                      const AuditTrail::Filter& filter);

}  // namespace tiltgate
