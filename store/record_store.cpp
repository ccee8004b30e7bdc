// RecordStore at work (store/record_store.h): appends, the budget, the replay and its cursor,
// and what a disk that refuses costs; opening is record_store_open.cpp's.
#include "store/record_store.h"

#include <fcntl.h>

#include <algorithm>
#include <cstdio>
#include <system_error>
#include <utility>

#include "store/store_layout.h"

namespace tiltgate::store {
namespace {

namespace fs = std::filesystem;

}  // namespace

RecordStore::RecordStore(std::filesystem::path dir, StoreOptions options)
    : dir_(std::move(dir)), options_(options) {}

RecordStore::~RecordStore() {
  if (writer_.valid()) (void)sync();
}

std::filesystem::path RecordStore::segment_path(std::uint64_t id) const {
  char name[kIdDigits + 5];
  std::snprintf(name, sizeof name, "%020llu.seg", static_cast<unsigned long long>(id));
  return dir_ / name;
}

Expected<Done, std::string> RecordStore::start_segment() {
  if (writer_.valid()) {
    if (auto synced = sync_files(); !synced) return synced;
    writer_.reset();
  }
  const std::uint64_t id = next_id_++;
  const fs::path path = segment_path(id);
  auto fd = open_file(path, O_WRONLY | O_CREAT | O_EXCL | O_APPEND);
  if (!fd) return Unexpected(fd.error());
  if (auto written = write_all(fd->get(), kSegmentMagic, path); !written) {
    std::error_code error;
    fs::remove(path, error);  // a header cut short: nothing of the store's in it
    return written;
  }
  writer_ = std::move(*fd);
  if (segments_.empty()) {
    cursor_offset_ = kSegmentHeaderBytes;
    cursor_index_ = 0;
  }
  segments_.push_back(Segment{id, kSegmentHeaderBytes, 0});
  bytes_ += kSegmentHeaderBytes;
  names_unsynced_ = true;
  return Done{};
}

void RecordStore::forget_front() {
  const Segment front = segments_.front();
  if (segments_.size() == 1) writer_.reset();
  if (reader_id_ == front.id) reader_.reset();
  segments_.pop_front();
  bytes_ -= front.size;
  records_ -= front.records;
  cursor_offset_ = kSegmentHeaderBytes;
  cursor_index_ = 0;
  names_unsynced_ = true;
  std::error_code error;
  fs::remove(segment_path(front.id), error);
  if (error) note_fault("cannot remove " + segment_path(front.id).string() + ": " + error.message());
}

void RecordStore::drop_oldest() {
  dropped_ += segments_.front().records - cursor_index_;
  forget_front();
}

void RecordStore::make_room(std::uint64_t size, bool keep_last_segment) {
  while (bytes_ + memory_bytes_ + size > options_.budget_bytes) {
    if (segments_.size() > (keep_last_segment ? 1u : 0u)) {
      drop_oldest();
    } else if (!memory_.empty()) {
      memory_bytes_ -= frame_size(memory_.front());
      memory_.pop_front();
      ++dropped_;
    } else {
      return;
    }
  }
}

Expected<Done, std::string> RecordStore::write_record(const Record& record, bool room) {
  const std::uint64_t size = frame_size(record);
  if (segments_.empty() || !writer_.valid() ||
      segments_.back().size + size > options_.segment_bytes) {
    if (auto started = start_segment(); !started) return started;
  }
  if (room) make_room(size, true);
  Segment& last = segments_.back();
  const fs::path path = segment_path(last.id);
  if (auto written = write_all(writer_.get(), frame(record), path); !written) {
    (void)truncate_file(path, last.size);  // no half record left behind
    // Should the cut have failed too, nothing more goes after what may be a half record.
    writer_.reset();
    return written;
  }
  last.size += size;
  ++last.records;
  bytes_ += size;
  ++records_;
  ++unsynced_;
  return Done{};
}

void RecordStore::keep_in_memory(const Record& record) {
  const std::uint64_t size = frame_size(record);
  make_room(size, false);
  memory_.push_back(record);
  memory_bytes_ += size;
}

Expected<Done, std::string> RecordStore::append(const Record& record) {
  const std::uint64_t size = frame_size(record);
  if (record.topic.size() > 0xFFFF || size - kFrameHeaderBytes > kMaxBodyBytes ||
      kSegmentHeaderBytes + size > options_.segment_bytes) {
    return Unexpected("a record of " + std::to_string(size) + " bytes does not fit a segment of " +
                      std::to_string(options_.segment_bytes));
  }
  // After records held in memory, a record waits in memory too: the order stays the append
  // order.
  if (memory_.empty()) {
    if (auto written = write_record(record, true); written) {
      if (unsynced_ >= options_.sync_every) (void)sync_files();
      return Done{};
    } else {
      note_fault(written.error());
    }
  }
  keep_in_memory(record);
  return Done{};
}

Expected<Done, std::string> RecordStore::sync_files() {
  if (writer_.valid() && unsynced_ > 0) {
    if (auto synced = sync_file(writer_.get(), segment_path(segments_.back().id)); !synced) {
      note_fault(synced.error());
      return synced;
    }
  }
  unsynced_ = 0;
  if (names_unsynced_) {
    if (auto synced = sync_directory(dir_); !synced) {
      note_fault(synced.error());
      return synced;
    }
    names_unsynced_ = false;
  }
  return Done{};
}

Expected<Done, std::string> RecordStore::sync() {
  retry_disk();
  return sync_files();
}

void RecordStore::retry_disk() {
  if (!fault_) return;
  if (cursor_unsaved_) {
    save_cursor();
    if (cursor_unsaved_) return;
  }
  std::uint64_t written = 0;
  while (!memory_.empty()) {
    if (auto done = write_record(memory_.front(), false); !done) {
      note_fault(done.error());
      return;
    }
    memory_bytes_ -= frame_size(memory_.front());
    memory_.pop_front();
    ++written;
  }
  fault_.reset();
  notices_.push_back({false, "the disk takes writes again" +
                                 (written > 0 ? ": " + records_text(written) +
                                                    " kept in memory meanwhile written out"
                                              : std::string())});
}

void RecordStore::note_fault(const std::string& error) {
  if (!fault_)
    notices_.push_back({true, error + "; until the disk takes writes again, records are kept in "
                                      "memory (within the budget, lost on a restart) and the "
                                      "replay goes on from its place in memory"});
  fault_ = error;
}

std::vector<StoreNotice> RecordStore::take_notices() { return std::exchange(notices_, {}); }

bool RecordStore::skip_finished(Position& at) const {
  while (at.segment < segments_.size() && at.offset >= segments_[at.segment].size) {
    ++at.segment;
    at.offset = kSegmentHeaderBytes;
    at.index = 0;
  }
  return at.segment < segments_.size();
}

Expected<FrameRead, std::string> RecordStore::read_at(Position& at) {
  const Segment& segment = segments_[at.segment];
  const fs::path path = segment_path(segment.id);
  if (!reader_.valid() || reader_id_ != segment.id) {
    auto fd = open_file(path, O_RDONLY);
    if (!fd) return Unexpected(fd.error());
    reader_ = std::move(*fd);
    reader_id_ = segment.id;
  }
  std::vector<std::uint8_t> bytes(kFrameHeaderBytes);
  auto n = store::read_at(reader_.get(), bytes, at.offset, path);
  if (!n) return Unexpected(n.error());
  bytes.resize(*n);  // shorter only if the file was cut behind the store's back
  const std::uint64_t body = *n == kFrameHeaderBytes ? frame_body_length(bytes) : 0;
  if (body > 0 && body <= kMaxBodyBytes && kFrameHeaderBytes + body <= segment.size - at.offset) {
    bytes.resize(kFrameHeaderBytes + body);
    auto rest = store::read_at(reader_.get(), std::span(bytes).subspan(kFrameHeaderBytes),
                               at.offset + kFrameHeaderBytes, path);
    if (!rest) return Unexpected(rest.error());
    bytes.resize(kFrameHeaderBytes + *rest);
  }
  FrameRead frame = read_frame(bytes);
  if (frame.status == FrameStatus::whole) {
    at.offset += frame.size;
    ++at.index;
  }
  return frame;
}

Expected<Done, std::string> RecordStore::cut_segment(const Position& at) {
  Segment& segment = segments_[at.segment];
  const std::uint64_t lost = segment.records - at.index;
  if (auto cut = truncate_file(segment_path(segment.id), at.offset); !cut) return cut;
  lost_ += lost;
  records_ -= lost;
  bytes_ -= segment.size - at.offset;
  segment.records = at.index;
  segment.size = at.offset;
  notices_.push_back({true, segment_path(segment.id).filename().string() +
                                ": a corrupt record found at byte " + std::to_string(at.offset) +
                                " while replaying: cut there, " + records_text(lost) + " lost"});
  return Done{};
}

Expected<std::vector<Record>, std::string> RecordStore::peek(std::size_t n) {
  std::vector<Record> out;
  Position at{0, cursor_offset_, cursor_index_};
  while (out.size() < n && skip_finished(at)) {
    auto frame = read_at(at);
    if (!frame) return Unexpected(frame.error());
    if (frame->status == FrameStatus::whole) {
      out.push_back(std::move(frame->record));
    } else if (auto cut = cut_segment(at); !cut) {
      return Unexpected(cut.error());
    }
  }
  for (std::size_t i = 0; out.size() < n && i < memory_.size(); ++i) out.push_back(memory_[i]);
  return out;
}

Expected<Done, std::string> RecordStore::pop(std::size_t n) {
  Position at{0, cursor_offset_, cursor_index_};
  std::size_t popped = 0;
  while (popped < n && skip_finished(at)) {
    auto frame = read_at(at);
    if (!frame) return Unexpected(frame.error());
    if (frame->status != FrameStatus::whole) {
      if (auto cut = cut_segment(at); !cut) return Unexpected(cut.error());
      continue;
    }
    ++popped;
  }
  std::size_t from_memory = 0;
  for (; popped + from_memory < n && !memory_.empty(); ++from_memory) {
    memory_bytes_ -= frame_size(memory_.front());
    memory_.pop_front();
  }
  replayed_ += popped + from_memory;
  if (popped == 0) return Done{};
  // Where the replay now stands, durably first; then the segments it has finished go (a crash
  // in between leaves them for open() to remove). A disk that refuses the cursor does not hold
  // the replay back: it goes on from its place in memory, saved once the disk takes it.
  skip_finished(at);
  const bool all_done = at.segment >= segments_.size();
  const Segment& reached = all_done ? segments_.back() : segments_[at.segment];
  if (auto written = write_cursor(reached.id, all_done ? reached.size : at.offset); !written) {
    cursor_unsaved_ = true;
    note_fault(written.error());
  } else {
    cursor_unsaved_ = false;
  }
  const std::size_t finished = all_done ? segments_.size() : at.segment;
  for (std::size_t i = 0; i < finished; ++i) forget_front();
  if (!all_done) {
    cursor_offset_ = at.offset;
    cursor_index_ = at.index;
  }
  return Done{};
}

void RecordStore::save_cursor() {
  // With no segment left, the next one's start: every file before it is replayed.
  const auto written = segments_.empty()
                           ? write_cursor(next_id_, kSegmentHeaderBytes)
                           : write_cursor(segments_.front().id, cursor_offset_);
  if (written) {
    cursor_unsaved_ = false;
  } else {
    cursor_unsaved_ = true;
    note_fault(written.error());
  }
}

Expected<Done, std::string> RecordStore::write_cursor(std::uint64_t id, std::uint64_t offset) {
  return replace_file(dir_ / kCursorName, cursor_bytes(Cursor{id, offset}));
}

}  // namespace tiltgate::store
