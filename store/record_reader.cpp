#include "store/record_reader.h"

#include <algorithm>
#include <map>
#include <span>
#include <system_error>

#include "store/file_io.h"
#include "store/store_layout.h"

namespace tiltgate::store {

Expected<std::vector<Record>, std::string> read_records(const std::filesystem::path& dir) {
  std::error_code ec;
  std::map<std::uint64_t, std::filesystem::path> segments;  // by id: append order
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
    if (auto id = segment_id(entry.path())) segments.emplace(*id, entry.path());
  if (ec) return Unexpected("cannot list " + dir.string() + ": " + ec.message());
  std::vector<Record> records;
  for (const auto& [id, path] : segments) {
    auto bytes = read_whole(path);
    if (!bytes) return Unexpected(bytes.error());
    const std::span<const std::uint8_t> all(*bytes);
    if (all.size() < kSegmentHeaderBytes ||
        !std::equal(kSegmentMagic.begin(), kSegmentMagic.end(), all.begin()))
      continue;  // not (yet) a segment: one being created
    for (std::size_t at = kSegmentHeaderBytes; at < all.size();) {
      FrameRead read = read_frame(all.subspan(at));
      if (read.status != FrameStatus::whole) break;
      records.push_back(std::move(read.record));
      at += read.size;
    }
  }
  return records;
}

}  // namespace tiltgate::store
