// The audit trail's writer (audit/audit_trail.h): a thread of its own that takes the records
// to disk, so that recording one never waits for a disk. The trail records on the buses'
// thread for every write carried out (issue 51: nothing slow runs there), and a Modbus client
// allowed to write must not be able to make that thread sync a disk as often as it likes.
//
// Batches: whatever queued up while the writer was busy goes to the sink at once, one call for
// all of it (the trail's: one append each and one sync for the batch).
//
// A disk that refuses: the sink keeps what it could not write (the store holds it in memory,
// store/record_store.h) and says so; the writer tries again kAuditRetryAfter later (at once
// for a flush() or close()), with what queued up meanwhile. Nothing is dropped here.
//
// Threads: push(), flush() and close() from any thread; the sink is called on the writer's
// thread, one call at a time (after close(), on the caller's).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "audit/audit_record.h"

namespace tiltgate {

inline constexpr std::chrono::milliseconds kAuditRetryAfter{1000};

class AuditWriter {
 public:
  // Appends `batch` (empty: nothing new, only what it still holds) after what it holds from
  // earlier calls, and syncs it all; true when everything it holds is on disk.
  using Sink = std::function<bool(const std::vector<AuditRecord>& batch)>;

  // Starts the thread.
  explicit AuditWriter(Sink sink, std::chrono::milliseconds retry_after = kAuditRetryAfter);
  ~AuditWriter();  // close()
  AuditWriter(const AuditWriter&) = delete;
  AuditWriter& operator=(const AuditWriter&) = delete;

  // Queues `record` for the writer and returns: never waits for the disk. After close() (at
  // shutdown, when nobody waits on the caller any more) the record is written at once.
  void push(AuditRecord record);
  // Has the writer write what is queued now, and waits for it: true when it is on disk, false
  // when the disk refused it (held, and tried again later).
  bool flush();
  // Writes what is queued (one last try: what the disk refuses now is lost with the process)
  // and ends the thread; true when everything is on disk. Idempotent.
  bool close();
  // Calls of the sink so far: one sync each.
  std::uint64_t batches() const;

 private:
  void run();  // the thread
  void write(const std::vector<AuditRecord>& batch);  // with mutex_ held, after close()

  Sink sink_;
  std::chrono::milliseconds retry_after_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;      // the writer: something to write, a flush, close()
  std::condition_variable answered_;  // flush(): its batch was written (or refused)
  std::deque<AuditRecord> queue_;
  std::uint64_t asked_ = 0;         // flush() calls
  std::uint64_t answered_for_ = 0;  // flush() calls the latest batch covered
  bool refused_ = false;            // the latest batch: the disk refused (part of) it
  bool closing_ = false;
  bool closed_ = false;             // the thread has ended: push() writes itself
  std::uint64_t batches_ = 0;
  std::thread thread_;  // last: it starts once everything above is made
};

}  // namespace tiltgate
