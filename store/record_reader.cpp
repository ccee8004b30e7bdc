#include "store/record_reader.h"

#include <algorithm>
#include <map>
#include <span>
#include <system_error>

#include "store/file_io.h"
#include "store/store_layout.h"

namespace tiltgate::store {

Expected<std::vector<SegmentRecords>, std::string> read_segments(
    const std::filesystem::path& dir) {
  std::error_code ec;
  std::map<std::uint64_t, std::filesystem::path> files;  // by id: append order
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
    if (auto id = segment_id(entry.path())) files.emplace(*id, entry.path());
  if (ec) return Unexpected("cannot list " + dir.string() + ": " + ec.message());
  std::vector<SegmentRecords> segments;
  for (const auto& [id, path] : files) {
    auto bytes = read_whole(path);
    if (!bytes) return Unexpected(bytes.error());
    const std::span<const std::uint8_t> all(*bytes);
    if (all.size() < kSegmentHeaderBytes ||
        !std::equal(kSegmentMagic.begin(), kSegmentMagic.end(), all.begin()))
      continue;  // not (yet) a segment: one being created
    SegmentRecords segment{id, path.filename().string(), {}, std::nullopt};
    for (std::size_t at = kSegmentHeaderBytes; at < all.size();) {
      FrameRead read = read_frame(all.subspan(at));
      if (read.status != FrameStatus::whole) {
        segment.damage = "at byte " + std::to_string(at) +
                         (read.status == FrameStatus::cut_short ? ": a record cut short"
                                                                : ": a corrupt record");
        break;
      }
      segment.records.push_back(std::move(read.record));
      at += read.size;
    }
    segments.push_back(std::move(segment));
  }
  return segments;
}

Expected<std::vector<Record>, std::string> read_records(const std::filesystem::path& dir) {
  auto segments = read_segments(dir);
  if (!segments) return Unexpected(segments.error());
  std::vector<Record> records;
  for (SegmentRecords& segment : *segments)
    for (Record& record : segment.records) records.push_back(std::move(record));
  return records;
}

}  // namespace tiltgate::store
