// A bounded, crash-safe store-and-forward on disk (docs/northbound.md, "The store"): messages
// that could not be published while the broker was away, kept in a directory (`state_dir`)
// across restarts and power cuts, and handed back oldest first when it is back. Generic: a
// record is a topic, a payload, a time and a QoS, whoever publishes it.
//
// The directory holds append-only segment files (00000000000000000001.seg, ...), each an
// 8-byte header then records framed as store/record_frame.h describes (a length and a CRC-32
// each), and a `cursor` file: how far the replay has come.
//
// Durability: an append is write(2) to the newest segment, so a crash of the process loses
// nothing appended; fsync runs every `sync_every` appends and on sync() (the caller's timer,
// once a second say), so a power cut loses at most what was appended since the last one. A
// write torn by a crash leaves at most the last record incomplete: reopening scans every
// segment to its last whole record with a valid CRC and cuts the file there, so the store
// always opens. A record with a wrong CRC in the middle of a segment (the disk, not a crash)
// ends that segment at the last good record before it.
//
// Budget: the segment files and the records held in memory (below) never take more than
// `budget_bytes`; an append that would exceed it drops the oldest first (whole segments, then
// records in memory), and counts the records not yet replayed among them in dropped().
//
// A disk that refuses (full, read-only, a directory where a file should be): an append it
// refuses is kept in memory after the records on disk, within the budget, and written out by
// the first sync() that the disk takes again; a cursor it refuses stays in memory (the replay
// goes on from there; a restart before it is written replays from the last one written) and
// is written by the next pop() or sync() the disk takes. What is in memory is lost on a
// restart. Each change (refusing, taking again) is one notice (take_notices()) for the log.
//
// Damage: records lost to a corrupt or torn record (it, and the rest of its segment after it,
// whose lengths cannot be trusted) are counted in lost(), and said in a notice or a repair.
//
// Replay: peek(n) gives the oldest n records not yet replayed, in append order; pop(n), after
// the caller has published them, moves the cursor past them, writes it to the `cursor` file
// (atomically: a new file renamed over the old) and deletes segments replayed to their end.
// After a restart the replay goes on from the cursor: what was popped is not given again.
// Delivery is at least once: a crash between publishing and pop() gives that batch again.
//
// Single-threaded: one owner (the caller's event loop) calls it; no locks.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "store/file_io.h"
#include "store/record_frame.h"

namespace tiltgate::store {

// Something the owner should log: a problem (the disk refusing, damage found) or its end.
struct StoreNotice {
  bool problem = false;
  std::string text;
};

struct StoreOptions {
  std::uint64_t budget_bytes = 64ull * 1024 * 1024;  // [sparkplug] buffer_mb
  // A segment is at most this long (and at most budget_bytes / 2): what a drop loses at once.
  std::uint64_t segment_bytes = 4ull * 1024 * 1024;
  std::size_t sync_every = 64;  // appends between two fsyncs; 1: every append
};

class RecordStore {
 public:
  // Opens (or creates) the store in `dir`, repairing what a crash left: a torn or corrupt
  // tail is cut off, segments already replayed are deleted. Fails when the directory cannot be
  // created or read, or the options do not fit (a segment must hold a record, the budget two
  // segments).
  static Expected<RecordStore, std::string> open(const std::filesystem::path& dir,
                                                 StoreOptions options = {});

  RecordStore(RecordStore&&) noexcept = default;
  RecordStore& operator=(RecordStore&&) noexcept = default;
  ~RecordStore();  // syncs what was appended

  // Fails for a record larger than a segment (or a topic over 65535 bytes): the record is then
  // not stored, and the store stays as it was. One the disk refuses is kept in memory.
  Expected<Done, std::string> append(const Record& record);
  // The oldest `n` records not yet replayed (fewer when there are fewer). A record found
  // corrupt now ends its segment there: the records after it in that segment are dropped.
  Expected<std::vector<Record>, std::string> peek(std::size_t n);
  // The oldest `n` records are replayed: the next peek() starts after them, now and after a
  // restart (once the disk takes the cursor).
  Expected<Done, std::string> pop(std::size_t n);
  // Writes out what the disk refused before, when it takes it now; fsync of what was appended
  // since the last one, and of the directory's names.
  Expected<Done, std::string> sync();
  // What happened since the last call, oldest first.
  std::vector<StoreNotice> take_notices();

  std::uint64_t bytes() const { return bytes_; }  // the segment files' size on disk
  // Not yet replayed, on disk and in memory.
  std::uint64_t records() const { return records_ - cursor_index_ + memory_.size(); }
  std::uint64_t in_memory() const { return memory_.size(); }  // refused by the disk, kept
  std::uint64_t in_memory_bytes() const { return memory_bytes_; }  // their frames' bytes
  std::uint64_t dropped() const { return dropped_; }    // since open(): dropped for the budget
  std::uint64_t lost() const { return lost_; }          // since open(): lost to damage
  // The disk's last refusal while one lasts (records or the cursor held in memory).
  const std::optional<std::string>& disk_fault() const { return fault_; }
  std::uint64_t replayed() const { return replayed_; }  // since open(): popped
  const std::filesystem::path& directory() const { return dir_; }
  // What open() repaired, one line each ("00000000000000000003.seg: cut at byte 1234: a record
  // cut short"), for the log.
  const std::vector<std::string>& repairs() const { return repairs_; }

 private:
  struct Segment {
    std::uint64_t id = 0;
    std::uint64_t size = 0;  // bytes, its header included
    std::uint64_t records = 0;
  };
  struct Position {
    std::size_t segment = 0;   // in segments_
    std::uint64_t offset = 0;  // of the next record in it
    std::uint64_t index = 0;   // records of that segment before it
  };

  RecordStore(std::filesystem::path dir, StoreOptions options);

  std::filesystem::path segment_path(std::uint64_t id) const;
  Expected<Done, std::string> scan_existing(std::uint64_t cursor_id, std::uint64_t cursor_offset,
                                            bool have_cursor);
  // scan_existing()'s steps. The segment files by id, directories in their way cleared.
  Expected<std::map<std::uint64_t, std::filesystem::path>, std::string> list_segment_files();
  // One segment file read back: kept, cut at its first bad record, or removed without a
  // header. `cursor_here`: the cursor is in it, at `cursor_offset`.
  Expected<Done, std::string> scan_segment(std::uint64_t id, const std::filesystem::path& path,
                                           bool cursor_here, std::uint64_t cursor_offset);
  // The cursor placed after its record count in the front segment, segments replayed to their
  // end forgotten, and the last segment opened for appends.
  Expected<Done, std::string> place_cursor();
  Expected<Done, std::string> start_segment();
  // Writes the record at the end of the last segment (a new one when it is full); makes room
  // for it within the budget first when `make_room`.
  Expected<Done, std::string> write_record(const Record& record, bool make_room);
  void keep_in_memory(const Record& record);
  // Drops the oldest until `size` more bytes fit the budget; the segment appended to stays
  // when `keep_last_segment`.
  void make_room(std::uint64_t size, bool keep_last_segment);
  void drop_oldest();
  // The oldest segment leaves the store; its file is removed (a failure is a disk fault: the
  // file is left for open() to find).
  void forget_front();
  Expected<Done, std::string> write_cursor(std::uint64_t id, std::uint64_t offset);
  // The cursor where the replay stands now, when the disk takes it.
  void save_cursor();
  // Records and a cursor the disk refused, written out when it takes them now.
  void retry_disk();
  Expected<Done, std::string> sync_files();
  void note_fault(const std::string& error);
  // The frame at `at`, read from its segment file; moves `at` past it.
  Expected<FrameRead, std::string> read_at(Position& at);
  Expected<Done, std::string> cut_segment(const Position& at);
  bool skip_finished(Position& at) const;

  std::filesystem::path dir_;
  StoreOptions options_;
  std::deque<Segment> segments_;  // oldest first; the last one is appended to
  UniqueFd writer_;               // the last segment's, for appending
  UniqueFd reader_;               // some segment's, for peek()
  std::uint64_t reader_id_ = 0;
  std::size_t unsynced_ = 0;
  bool names_unsynced_ = false;  // a segment created or removed since the directory's fsync
  // The replay's position in segments_.front(): the next record's offset, and how many of the
  // segment's records come before it.
  std::uint64_t cursor_offset_ = 0;
  std::uint64_t cursor_index_ = 0;
  std::uint64_t next_id_ = 1;
  std::uint64_t bytes_ = 0;
  std::uint64_t records_ = 0;  // in the segments, replayed or not
  std::uint64_t dropped_ = 0;
  std::uint64_t lost_ = 0;
  std::uint64_t replayed_ = 0;
  std::vector<std::string> repairs_;
  // Records the disk refused, after every record on disk, oldest first; their frames' bytes.
  std::deque<Record> memory_;
  std::uint64_t memory_bytes_ = 0;
  bool cursor_unsaved_ = false;  // the replay's place is ahead of the `cursor` file
  std::optional<std::string> fault_;
  std::vector<StoreNotice> notices_;
};

}  // namespace tiltgate::store
