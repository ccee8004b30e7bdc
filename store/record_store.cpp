#include "store/record_store.h"

#include <fcntl.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <optional>
#include <system_error>
#include <utility>

#include "store/crc32.h"

namespace tiltgate::store {
namespace {

namespace fs = std::filesystem;

// The first bytes of every segment file: a file of the store, in this format.
constexpr std::array<std::uint8_t, 8> kSegmentMagic = {'t', 'g', 's', 't', 'o', 'r', 'e', '1'};
constexpr std::uint64_t kSegmentHeaderBytes = kSegmentMagic.size();
// The cursor file: a magic, the segment id and offset the replay has reached, their CRC-32.
constexpr std::array<std::uint8_t, 8> kCursorMagic = {'t', 'g', 'c', 'u', 'r', 's', 'o', 'r'};
constexpr std::size_t kCursorBytes = 8 + 8 + 8 + 4;
constexpr const char* kCursorName = "cursor";
constexpr std::size_t kIdDigits = 20;

void put_u64(std::vector<std::uint8_t>& out, std::uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

std::uint64_t get_u64(std::span<const std::uint8_t> in) {
  std::uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<std::uint64_t>(in[i]) << (8 * i);
  return v;
}

// The id in a segment file's name (twenty digits, ".seg"), none for any other file.
std::optional<std::uint64_t> segment_id(const fs::path& path) {
  const std::string name = path.filename().string();
  if (name.size() != kIdDigits + 4 || name.substr(kIdDigits) != ".seg") return std::nullopt;
  std::uint64_t id = 0;
  for (std::size_t i = 0; i < kIdDigits; ++i) {
    if (name[i] < '0' || name[i] > '9') return std::nullopt;
    id = id * 10 + static_cast<std::uint64_t>(name[i] - '0');
  }
  return id;
}

struct Cursor {
  std::uint64_t id = 0;
  std::uint64_t offset = 0;
};

std::optional<Cursor> parse_cursor(std::span<const std::uint8_t> bytes) {
  if (bytes.size() != kCursorBytes ||
      !std::equal(kCursorMagic.begin(), kCursorMagic.end(), bytes.begin())) {
    return std::nullopt;
  }
  std::uint32_t crc = 0;
  for (int i = 0; i < 4; ++i) crc |= static_cast<std::uint32_t>(bytes[24 + i]) << (8 * i);
  if (crc32(bytes.first(24)) != crc) return std::nullopt;
  return Cursor{get_u64(bytes.subspan(8, 8)), get_u64(bytes.subspan(16, 8))};
}

// "1 record", "3 records".
std::string records_text(std::uint64_t n) {
  return std::to_string(n) + (n == 1 ? " record" : " records");
}

// The whole records in `all` after a damaged one at `from`, found by trying each later byte as
// the start of a frame: a frame's CRC-32 makes a false find as unlikely as a missed error.
std::uint64_t whole_records_after(std::span<const std::uint8_t> all, std::uint64_t from) {
  std::uint64_t found = 0;
  std::uint64_t at = from + 1;
  while (at + kFrameHeaderBytes + kBodyFixedBytes <= all.size()) {
    const auto rest = all.subspan(at);
    const std::uint32_t body = frame_body_length(rest);
    if (body >= kBodyFixedBytes && body <= rest.size() - kFrameHeaderBytes &&
        rest[kFrameHeaderBytes] == kFrameFormat) {
      const FrameRead frame = read_frame(rest);
      if (frame.status == FrameStatus::whole) {
        ++found;
        at += frame.size;
        continue;
      }
    }
    ++at;
  }
  return found;
}

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

Expected<RecordStore, std::string> RecordStore::open(const std::filesystem::path& dir,
                                                     StoreOptions options) {
  options.segment_bytes = std::min(options.segment_bytes, options.budget_bytes / 2);
  if (options.segment_bytes < kSegmentHeaderBytes + kFrameHeaderBytes + kBodyFixedBytes + 64) {
    return Unexpected(std::string("the store's budget is too small to hold a segment"));
  }
  options.sync_every = std::max<std::size_t>(options.sync_every, 1);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) return Unexpected("cannot create " + dir.string() + ": " + error.message());
  RecordStore store(dir, options);
  const std::string cursor_tmp = std::string(kCursorName) + ".tmp";
  for (const std::string& name : {std::string(kCursorName), cursor_tmp}) {
    auto cleared = clear_way_for_file(dir / name);
    if (!cleared) return Unexpected(cleared.error());
    if (*cleared) store.repairs_.push_back(**cleared);
  }
  fs::remove(dir / cursor_tmp, error);  // a cursor write cut short

  std::optional<Cursor> cursor;
  if (fs::exists(dir / kCursorName, error)) {
    auto bytes = read_whole(dir / kCursorName);
    if (!bytes) return Unexpected(bytes.error());
    cursor = parse_cursor(*bytes);
    if (!cursor)
      store.repairs_.push_back("cursor: unreadable, the replay starts at the oldest record");
  }
  auto scanned =
      store.scan_existing(cursor ? cursor->id : 0, cursor ? cursor->offset : 0, cursor.has_value());
  if (!scanned) return Unexpected(scanned.error());
  if (auto synced = sync_directory(dir); !synced) return Unexpected(synced.error());
  return store;
}

Expected<Done, std::string> RecordStore::scan_existing(std::uint64_t cursor_id,
                                                       std::uint64_t cursor_offset,
                                                       bool have_cursor) {
  // New segments get ids past every file's and the cursor's: one numbered below the cursor
  // would be taken for replayed at the next open.
  if (have_cursor) next_id_ = std::max(next_id_, cursor_id + 1);
  std::map<std::uint64_t, fs::path> files;
  std::error_code error;
  std::vector<fs::path> in_the_way;  // directories with a segment's name
  for (const auto& entry : fs::directory_iterator(dir_, error)) {
    if (auto id = segment_id(entry.path())) {
      std::error_code type_error;
      if (entry.symlink_status(type_error).type() == fs::file_type::directory)
        in_the_way.push_back(entry.path());
      else
        files[*id] = entry.path();
    }
  }
  if (error) return Unexpected("cannot list " + dir_.string() + ": " + error.message());
  for (const fs::path& path : in_the_way) {
    auto cleared = clear_way_for_file(path);
    if (!cleared) return Unexpected(cleared.error());
    if (*cleared) repairs_.push_back(**cleared);
  }
  for (const auto& [id, path] : files) {
    next_id_ = std::max(next_id_, id + 1);
    if (have_cursor && id < cursor_id) {  // replayed, and its deletion was cut short
      fs::remove(path, error);
      continue;
    }
    auto bytes = read_whole(path);
    if (!bytes) return Unexpected(bytes.error());
    const std::span<const std::uint8_t> all(*bytes);
    if (all.size() < kSegmentHeaderBytes ||
        !std::equal(kSegmentMagic.begin(), kSegmentMagic.end(), all.begin())) {
      repairs_.push_back(path.filename().string() + ": no segment header, removed");
      fs::remove(path, error);
      continue;
    }
    Segment segment{id, kSegmentHeaderBytes, 0};
    const bool cursor_here = have_cursor && id == cursor_id;
    std::uint64_t before_cursor = 0;
    while (segment.size < all.size()) {
      const FrameRead frame = read_frame(all.subspan(segment.size));
      if (frame.status != FrameStatus::whole) {
        const std::uint64_t lost = 1 + whole_records_after(all, segment.size);
        lost_ += lost;
        repairs_.push_back(path.filename().string() + ": cut at byte " +
                           std::to_string(segment.size) +
                           (frame.status == FrameStatus::cut_short ? ": a record cut short"
                                                                   : ": a corrupt record") +
                           ", " + records_text(lost) + " lost");
        if (auto cut = truncate_file(path, segment.size); !cut) return cut;
        break;
      }
      if (cursor_here && segment.size < cursor_offset) ++before_cursor;
      segment.size += frame.size;
      ++segment.records;
    }
    // Without the cursor's segment (replayed and removed) the replay starts at the oldest.
    if (cursor_here) cursor_index_ = before_cursor;
    segments_.push_back(segment);
    bytes_ += segment.size;
    records_ += segment.records;
  }
  // The cursor sits after its record count in the front segment; segments replayed to their
  // end go (the last one too: appends start a new segment).
  Position front{0, kSegmentHeaderBytes, 0};
  cursor_offset_ = kSegmentHeaderBytes;
  for (std::uint64_t i = 0; i < cursor_index_; ++i) {
    auto frame = read_at(front);
    if (!frame) return Unexpected(frame.error());
  }
  cursor_offset_ = front.offset;
  while (!segments_.empty() && cursor_index_ == segments_.front().records &&
         (segments_.size() > 1 || segments_.front().records > 0)) {
    forget_front();
  }
  if (!segments_.empty()) {
    auto fd = open_file(segment_path(segments_.back().id), O_WRONLY | O_APPEND);
    if (!fd) return Unexpected(fd.error());
    writer_ = std::move(*fd);
  }
  return Done{};
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
  std::vector<std::uint8_t> bytes(kCursorMagic.begin(), kCursorMagic.end());
  put_u64(bytes, id);
  put_u64(bytes, offset);
  const std::uint32_t crc = crc32(bytes);
  for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<std::uint8_t>(crc >> (8 * i)));
  return replace_file(dir_ / kCursorName, bytes);
}

}  // namespace tiltgate::store
