#include "monitoring/record_file.h"

#include <fcntl.h>

#include <span>

#include "monitoring/record_format.h"

namespace tiltgate::monitoring {

Expected<RecordFileReader, std::string> RecordFileReader::open(const std::filesystem::path& path) {
  auto fd = store::open_file(path, O_RDONLY);
  if (!fd) return Unexpected(fd.error());
  FileHeader header{};
  auto got = store::read_at(fd->get(), header, 0, path);
  if (!got) return Unexpected(got.error());
  RecordFileReader reader(path, std::move(*fd));
  if (*got < kFileHeaderBytes) {
    reader.at_end_ = true;  // created, its header not yet written: nothing in it yet
    return reader;
  }
  if (!is_file_header(header))
    return Unexpected(path.string() + ": not a long record file of this format (its header)");
  reader.offset_ = kFileHeaderBytes;
  return reader;
}

Expected<RecordFileReader::Next, std::string> RecordFileReader::next() {
  if (used_ + kRecordBytes > chunk_.size()) {
    if (at_end_) return Next{};
    offset_ += used_;
    chunk_.resize(kChunkRecords * kRecordBytes);
    auto got = store::read_at(fd_.get(), chunk_, offset_, path_);
    if (!got) return Unexpected(got.error());
    // Whole records only: a shorter tail is a record being written, or one a crash tore.
    chunk_.resize(*got / kRecordBytes * kRecordBytes);
    used_ = 0;
    at_end_ = *got < kChunkRecords * kRecordBytes;
    if (chunk_.empty()) return Next{};
  }
  const auto bytes = std::span<const std::uint8_t>(chunk_).subspan(used_, kRecordBytes);
  used_ += kRecordBytes;
  auto record = decode_record(bytes);
  if (!record) return Next{Slot::corrupt, {}};
  return Next{Slot::record, *record};
}

}  // namespace tiltgate::monitoring
