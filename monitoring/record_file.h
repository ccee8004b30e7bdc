// One day file of the long record read a chunk at a time (monitoring/record_format.h): what
// both the range reader and the record's own opening (finding where it ends) walk through.
// Reads only, so it is safe beside the gateway appending to the same file: a record being
// written at that instant (shorter than a record) ends the reading, as a torn one would.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "monitoring/interval_record.h"
#include "store/file_io.h"

namespace tiltgate::monitoring {

class RecordFileReader {
 public:
  // Records read from the disk at once: 18 KiB, whatever the file's size.
  static constexpr std::size_t kChunkRecords = 256;

  // Opens the file and checks its header. A file shorter than a header (just created) reads as
  // no records. Fails when it cannot be opened or read, or its header is not this format's.
  static Expected<RecordFileReader, std::string> open(const std::filesystem::path& path);

  enum class Slot { record, corrupt, end };
  struct Next {
    Slot slot = Slot::end;
    IntervalRecord record;  // when `record`
  };
  // The next record's slot: a record, or `corrupt` for one whose CRC is wrong (skipped: the
  // next one follows it), or `end` past the last whole record. Fails when the disk cannot be
  // read.
  Expected<Next, std::string> next();

  const std::filesystem::path& path() const { return path_; }

 private:
  RecordFileReader(std::filesystem::path path, store::UniqueFd fd)
      : path_(std::move(path)), fd_(std::move(fd)) {}

  std::filesystem::path path_;
  store::UniqueFd fd_;
  std::uint64_t offset_ = 0;  // in the file, of chunk_'s first byte
  std::vector<std::uint8_t> chunk_;
  std::size_t used_ = 0;  // of chunk_'s bytes
  bool at_end_ = false;   // the last read came short: no more whole records
};

}  // namespace tiltgate::monitoring
