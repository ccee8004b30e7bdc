// A sensor's long record on disk (docs/monitoring.md, "The long record"): its closed intervals
// (monitoring/interval_summary.h) appended to one file per UTC day in a directory of its own
// (the owner's choice: STATE_DIR/record/SENSOR_NAME/), kept for `keep_days`, read back by time
// range (monitoring/long_record_reader.h). The files' bytes: monitoring/record_format.h.
//
// Order: an interval is written only when it starts at or after the end of the last one
// accepted (append() refuses it otherwise, counted), so every file, and the record, is in time
// order and no two intervals overlap. After a restart the owner seeds its IntervalSummary with
// written_until(), so a clock behind the record drops samples there rather than have whole
// intervals refused here.
//
// Durability: an append is one write(2) of the record (the new day file's header before it), so
// a crash of the process (SIGKILL, a segfault) loses nothing appended: only the interval still
// open in the owner's IntervalSummary. fdatasync runs every `sync_every` appends, when a day's
// file is left for the next, on sync() (the owner's timer) and when the record is destroyed, so
// a power cut loses at most what was appended since the last one (at the defaults, 10 intervals
// of 60 s), and a record cut short by it is cut off when the record is opened again. A record
// the disk garbled (zeros after a power cut) is skipped and counted by the reader.
//
// A disk that refuses (full, read-only, the directory gone or not writable): nothing throws,
// append() never fails. What the disk refuses is held in memory, in order, up to `hold_max`
// intervals (the oldest then lost, counted), and written out by the first append() or sync()
// the disk takes again; each failure is counted (disk_failures()), and a fault's start and end
// are one notice each (take_notices(), the store's StoreNotice) for the owner to log. What is
// held is lost if the process ends first.
//
// Retention: remove_expired(now) deletes whole day files, those older than `keep_days` before
// both the clock's day and the newest interval's day: a clock set wrong far ahead never wipes
// the record, and a sensor silent for a month keeps its last `keep_days`. So a record holds at
// most keep_days + 1 files (monitoring/record_budget.h).
//
// Single-threaded: one owner calls it. Readers need not go through it: LongRecordReader opens
// the files by name, from any thread or process.
#pragma once

#include <cstdint>
#include <deque>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "monitoring/interval_record.h"
#include "monitoring/long_record_reader.h"
#include "store/file_io.h"
#include "store/record_store.h"

namespace tiltgate::monitoring {

using RecordNotice = store::StoreNotice;

// Where a sensor's record lives: `<state_dir>/record/<sensor>/`. A configuration's sensor names
// are letters, digits, '_', '.' and '-' (toml/toml_reader.h), which lets a name be "." or "..":
// a leading '.' is written "%2E" ('%' is in no name), so every sensor has a folder of its own
// inside record/, and no two share one.
std::filesystem::path record_directory(const std::filesystem::path& state_dir,
                                       std::string_view sensor);
// The folder name of a sensor's own files, as above (the burst records use it too).
std::string sensor_folder_name(std::string_view sensor);

struct LongRecordOptions {
  std::uint32_t keep_days = 91;   // whole UTC days kept before the newest one
  std::uint32_t sync_every = 10;  // appends between two fdatasyncs; 1: every one; 0: sync() only
  std::size_t hold_max = 1440;    // intervals held in memory while the disk refuses (100 KiB)
};

class LongRecord {
 public:
  // Opens the record in `dir`, making the directory when it is missing, and repairs what a crash
  // left in its newest file (a record cut short is cut off, a header cut short written again, a
  // file whose header is damaged moved aside to NAME.damaged). Never fails: a directory that
  // cannot be made or read is a disk fault, tried again by every append() and sync().
  static LongRecord open(std::filesystem::path dir, LongRecordOptions options = {});

  LongRecord(LongRecord&&) noexcept = default;
  LongRecord& operator=(LongRecord&&) noexcept = default;
  ~LongRecord();  // syncs what was appended

  enum class Appended {
    written,  // on disk (synced as sync_every says)
    held,     // the disk refused it (or what came before it): in memory, written out later
    behind,   // refused: it does not start at or after written_until(); not kept
  };
  Appended append(const IntervalRecord& interval);

  // fdatasync of what was appended since the last one and of new files' names; first writes
  // out what the disk refused before, when it takes it now.
  void sync();

  // Deletes the day files older than keep_days before both `now_unix_ms`'s UTC day and the
  // newest interval's (none before the record's first interval is known). Returns how many.
  std::size_t remove_expired(std::int64_t now_unix_ms);

  // The intervals whose start is in [from, to), from the files: what was appended, not what is
  // held in memory.
  LongRecordReader read(std::int64_t from_unix_ms, std::int64_t to_unix_ms) const {
    return LongRecordReader(dir_, from_unix_ms, to_unix_ms);
  }

  // What happened since the last call, oldest first: a fault's start (problem) and its end.
  std::vector<RecordNotice> take_notices();

  // Where the last interval accepted (on disk or held) ends: an interval may start there or
  // later. None while the record is empty, or could not be read yet.
  std::optional<std::int64_t> written_until() const { return accepted_until_; }
  std::uint64_t appended() const { return appended_; }  // since open(): written to disk
  std::uint64_t behind() const { return behind_; }      // since open(): refused for their start
  std::uint64_t held() const { return held_.size(); }   // now: waiting for the disk
  std::uint64_t lost() const { return lost_; }          // since open(): past hold_max
  std::uint64_t disk_failures() const { return disk_failures_; }  // since open()
  std::uint64_t removed_files() const { return removed_files_; }  // since open()
  // The disk's last refusal while a fault lasts.
  const std::optional<std::string>& disk_fault() const { return fault_; }
  // What open() (or the first attach after a fault) repaired, one line each, for the log.
  const std::vector<std::string>& repairs() const { return repairs_; }
  const std::filesystem::path& directory() const { return dir_; }

 private:
  LongRecord(std::filesystem::path dir, LongRecordOptions options);

  // long_record_files.cpp: the directory and its files.
  // Reads the directory: repairs its newest file and finds where the record ends. False (a
  // fault noted) when the disk refuses.
  bool attach();
  // The day's file opened for appending as writer_, made with its header when new, repaired
  // as attach() says when not.
  Expected<Done, std::string> open_day(std::int64_t day);
  // Where the last valid record of the newest file that has one ends; none for no record. A
  // file that cannot be read is passed over (the reader names it).
  std::optional<std::int64_t> find_end(const std::vector<std::int64_t>& days_oldest_first) const;
  std::filesystem::path day_path(std::int64_t day) const;

  // long_record.cpp
  // Writes out what is held, oldest first, until the disk refuses: true when all is written.
  bool write_held();
  Expected<Done, std::string> write(const IntervalRecord& interval);
  Expected<Done, std::string> sync_files();
  void note_fault(const std::string& error);
  void note_recovery();

  std::filesystem::path dir_;
  LongRecordOptions options_;
  bool attached_ = false;  // the directory has been read: disk_end_ is known
  store::UniqueFd writer_;
  std::int64_t writer_day_ = 0;
  std::uint32_t unsynced_ = 0;   // appends since writer_'s last fdatasync
  bool names_unsynced_ = false;  // a file made, moved or removed since the directory's fsync
  std::optional<std::int64_t> disk_end_;        // where the last interval on disk ends
  std::optional<std::int64_t> accepted_until_;  // where the last one accepted ends
  std::deque<IntervalRecord> held_;
  std::uint64_t appended_ = 0;
  std::uint64_t behind_ = 0;
  std::uint64_t lost_ = 0;
  std::uint64_t disk_failures_ = 0;
  std::uint64_t removed_files_ = 0;
  // Counts of the fault under way, for the notice that ends it.
  std::uint64_t fault_lost_ = 0;
  bool behind_said_ = false;  // a notice for refused intervals given, until one is accepted
  std::optional<std::string> fault_;
  std::vector<std::string> repairs_;
  std::vector<RecordNotice> notices_;
};

}  // namespace tiltgate::monitoring
