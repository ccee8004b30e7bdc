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
//
// Durability: record() takes the record in memory at once (recent() and counts() see it) and
// queues it for the trail's writer thread (audit/audit_writer.h), which appends what queued up
// and syncs it to disk, one sync a batch, as soon as it can: a power cut loses at most the
// records of the moment. record() never waits for the disk: it is called on the buses' thread
// for every write carried out.
//
// A disk that refuses (docs/operations.md, "A disk that refuses the trail"): the records it
// refuses are held in memory, in order, up to AuditOptions::memory_budget_bytes, and written by
// the writer's next try (each second) and at close(). Past the budget a record is lost: logged
// at error, counted (health()), and once the disk takes the trail again one record says how
// many were lost and when. With when_full refuse, changes are refused while the disk refuses
// (accepts_changes()), as auditd's disk_full_action can halt what it cannot record.
//
// Tamper evidence: each record on disk carries the hash of the one before it
// (audit/audit_chain.h), chained by the writer thread, which also hands each record with its
// hash to the journal (AuditOptions::journal).
//
// Threads: any (one mutex; the store is the writer's once it runs). Owned by the composition
// root (app/served_gateway.h), which gives the gateway a reference to it; no global.
#pragma once

#include <cstddef>
#include <cstdint>
#include <atomic>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "audit/audit_chain.h"
#include "audit/audit_counts.h"
#include "audit/audit_record.h"
#include "audit/audit_writer.h"
#include "store/record_store.h"

namespace tiltgate {

inline constexpr std::size_t kAuditMaxRecords = 10000;
// Why a change is refused while accepts_changes() is false: the record's and the door's words.
inline constexpr std::string_view kAuditRefusesChanges =
    "the audit trail's disk refuses records and [audit] when_full is \"refuse\"";
inline constexpr std::uint64_t kAuditStoreBytes = 4ull * 1024 * 1024;
inline constexpr std::uint64_t kAuditSegmentBytes = 256ull * 1024;

// What the trail does when its disk refuses records ([audit] when_full,
// docs/configuration.md, "[audit]").
enum class AuditWhenFull {
  keep,    // changes go on; records held in memory, past the budget lost and counted
  refuse,  // changes are refused (and that recorded) until the disk takes the trail again
};

struct AuditOptions {
  std::uint64_t memory_budget_bytes = 1024ull * 1024;  // [audit] memory_kib
  AuditWhenFull when_full = AuditWhenFull::keep;
  // Each record as written, with its chain hash, on the writer's thread: the journal's
  // structured entry (app/audit_journal.h). Empty: none. When set, record() logs no
  // "audit: ..." line itself (the journal entry is that line).
  std::function<void(const AuditRecord&, const std::string& hash)> journal;
};

class AuditTrail {
 public:
  // state_dir empty: kept in memory only (tiltgate demo). An unusable folder: logged, memory
  // only.
  explicit AuditTrail(std::string state_dir, std::size_t max_records = kAuditMaxRecords);
  ~AuditTrail();  // close()
  AuditTrail(const AuditTrail&) = delete;
  AuditTrail& operator=(const AuditTrail&) = delete;

  // Keeps the trail in <state_dir>/audit/ from now on (the composition root calls it once the
  // gateway serves as its own user, so the files are that user's): the records found there
  // come first, then those recorded in memory meanwhile, which are written there too. Starts
  // the writer thread.
  void open(const std::string& state_dir, AuditOptions options = {});

  // Any thread; stamps the time when the record has none, and passes its text fields through
  // visible_text (driver/visible_text.h): the doors hand in what clients sent as it came. Also
  // logged: "audit: ...". Returns at once: the writer takes it to disk.
  void record(AuditRecord record);
  // Waits until what was recorded before is on disk; false when the disk refused it (kept in
  // memory, tried again) or the trail is in memory only.
  bool flush();
  // Writes everything queued and ends the writer thread; a record after it is written by its
  // caller. At shutdown, once nothing records any more. Idempotent.
  void close();

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
  // False while when_full is refuse and the disk refuses the trail: a change must be refused
  // then (and that refusal recorded). Any thread; the writer updates it after each try.
  bool accepts_changes() const;
  AuditHealth health() const;

 private:
  void keep(AuditRecord record);  // in memory, within max_records_
  // The writer's sink (AuditWriter::Sink): the batch appended to the store, and one sync.
  bool write_out(const std::vector<AuditRecord>& batch);
  void log_store_notices();
  // Appends one record with the chain's next link; false when the store cannot take it.
  void append_chained(const AuditRecord& record);
  // Whether `record` fits beside what the store holds in memory for a refusing disk; counts
  // and logs it as lost when not.
  bool fits_memory_budget(const AuditRecord& record);
  // Once the disk takes the trail again: the record that says what was lost meanwhile.
  void append_lost_notice();

  mutable std::mutex mutex_;
  std::size_t max_records_;
  std::deque<AuditRecord> records_;  // oldest first
  std::string folder_;    // where the trail is kept; empty while in memory only
  store::UniqueFd lock_;  // before the store: released after it closed
  std::optional<store::RecordStore> store_;  // touched by the writer alone once it runs
  std::unique_ptr<AuditWriter> writer_;      // after the store: it ends first
  bool closed_ = false;
  std::map<std::pair<std::string, std::string>, std::uint64_t> counts_;  // (door, class)
  AuditOptions options_;
  // The writer's own (write_out() and what it calls), set before it starts.
  std::string chain_head_;  // hash of the newest record on disk (or held for it)
  std::uint64_t lost_now_ = 0;  // lost since the disk last took the trail
  std::int64_t lost_first_ms_ = 0, lost_last_ms_ = 0;
  // Read by any thread.
  std::atomic<bool> disk_refuses_{false};
  std::atomic<bool> refusing_changes_{false};  // disk_refuses_ with when_full refuse
  std::atomic<std::uint64_t> held_{0};
  std::atomic<std::uint64_t> lost_total_{0};
};

// The folder the trail keeps in, under a state_dir: <state_dir>/audit.
std::string audit_folder(const std::string& state_dir);
// Every record a trail keeps in `folder`, oldest first, read without opening it (safe beside a
// running gateway: store/record_reader.h). Records that are not audit records are skipped.
Expected<std::vector<AuditRecord>, std::string> read_audit_folder(const std::string& folder);
// The chain of the records a trail keeps in `folder` checked (audit/audit_chain.h), with the
// first damaged frame: what `tiltgate audit --verify` says (audit_verify.cpp). Reads only.
Expected<AuditChainCheck, std::string> verify_audit_folder(const std::string& folder);
// The records of `all` (oldest first) that `filter` selects, newest first.
std::vector<AuditRecord> select_audit(const std::deque<AuditRecord>& all,
                                      const AuditTrail::Filter& filter);

}  // namespace tiltgate
