// RecordStore::open (store/record_store.h): the store's directory as a crash, a damaged disk or
// a hand left it, made usable again: a torn or corrupt tail cut off and what it cost counted,
// segments already replayed removed, directories where the store's files should be cleared
// away, the replay's place read back from the cursor.
#include <fcntl.h>

#include <algorithm>
#include <map>
#include <optional>
#include <system_error>

#include "store/record_store.h"
#include "store/store_layout.h"

namespace tiltgate::store {
namespace {

namespace fs = std::filesystem;

}  // namespace

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
  auto files = list_segment_files();
  if (!files) return Unexpected(files.error());
  for (const auto& [id, path] : *files) {
    next_id_ = std::max(next_id_, id + 1);
    if (have_cursor && id < cursor_id) {  // replayed, and its deletion was cut short
      std::error_code error;
      fs::remove(path, error);
      continue;
    }
    auto scanned = scan_segment(id, path, have_cursor && id == cursor_id, cursor_offset);
    if (!scanned) return scanned;
  }
  return place_cursor();
}

Expected<std::map<std::uint64_t, fs::path>, std::string> RecordStore::list_segment_files() {
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
  return files;
}

Expected<Done, std::string> RecordStore::scan_segment(std::uint64_t id, const fs::path& path,
                                                      bool cursor_here,
                                                      std::uint64_t cursor_offset) {
  auto bytes = read_whole(path);
  if (!bytes) return Unexpected(bytes.error());
  const std::span<const std::uint8_t> all(*bytes);
  if (all.size() < kSegmentHeaderBytes ||
      !std::equal(kSegmentMagic.begin(), kSegmentMagic.end(), all.begin())) {
    repairs_.push_back(path.filename().string() + ": no segment header, removed");
    std::error_code error;
    fs::remove(path, error);
    return Done{};
  }
  Segment segment{id, kSegmentHeaderBytes, 0};
  std::uint64_t before_cursor = 0;
  while (segment.size < all.size()) {
    const FrameRead frame = read_frame(all.subspan(segment.size));
    if (frame.status != FrameStatus::whole) {
      const std::uint64_t lost = 1 + whole_frames_after(all, segment.size);
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
  return Done{};
}

Expected<Done, std::string> RecordStore::place_cursor() {
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

}  // namespace tiltgate::store
