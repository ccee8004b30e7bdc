#include "monitoring/long_record_reader.h"

#include <algorithm>
#include <map>
#include <system_error>

#include "monitoring/record_format.h"
#include "monitoring/utc_time.h"

namespace tiltgate::monitoring {

LongRecordReader::LongRecordReader(std::filesystem::path dir, std::int64_t from_unix_ms,
                                   std::int64_t to_unix_ms)
    : dir_(std::move(dir)), from_(from_unix_ms), to_(to_unix_ms), finished_(to_ <= from_) {}

void LongRecordReader::list_files() {
  listed_ = true;
  // A file holds the intervals that start on its day: the range's first day to its last.
  const std::int64_t first_day = utc_day(from_);
  const std::int64_t last_day = utc_day(to_ - 1);
  std::map<std::int64_t, std::filesystem::path> by_day;
  std::error_code ec;
  std::filesystem::directory_iterator it(dir_, ec);
  if (ec) {
    if (ec != std::errc::no_such_file_or_directory)
      problems_.push_back("cannot list " + dir_.string() + ": " + ec.message());
    return;
  }
  for (; it != std::filesystem::directory_iterator(); it.increment(ec)) {
    const auto name = parse_record_file_name(it->path().filename().string());
    if (name && !name->damaged && name->day >= first_day && name->day <= last_day)
      by_day.emplace(name->day, it->path());
  }
  if (ec) problems_.push_back("cannot list " + dir_.string() + ": " + ec.message());
  for (auto& [day, path] : by_day) files_.push_back(std::move(path));
}

bool LongRecordReader::open_next_file() {
  while (next_file_ < files_.size()) {
    const std::filesystem::path& path = files_[next_file_++];
    auto opened = RecordFileReader::open(path);
    if (opened) {
      file_.emplace(std::move(*opened));
      return true;
    }
    // Removed by the retention since the listing: its days are before the range's end anyway.
    std::error_code ec;
    if (std::filesystem::exists(path, ec) || ec) problems_.push_back(opened.error());
  }
  return false;
}

std::vector<IntervalRecord> LongRecordReader::next(std::size_t max_rows) {
  std::vector<IntervalRecord> rows;
  if (finished_) return rows;
  if (!listed_) list_files();
  max_rows = std::max<std::size_t>(max_rows, 1);
  rows.reserve(std::min(max_rows, kDefaultBatch));
  while (rows.size() < max_rows) {
    if (!file_ && !open_next_file()) {
      finished_ = true;
      break;
    }
    auto next = file_->next();
    if (!next) {
      problems_.push_back(next.error());
      file_.reset();
      continue;
    }
    if (next->slot == RecordFileReader::Slot::end) {
      file_.reset();
      continue;
    }
    if (next->slot == RecordFileReader::Slot::corrupt) {
      ++corrupt_;
      continue;
    }
    const IntervalRecord& record = next->record;
    if (end_of_last_ && record.start_unix_ms < *end_of_last_) {
      ++out_of_order_;
      continue;
    }
    if (record.start_unix_ms < from_) continue;
    if (record.start_unix_ms >= to_) {
      // Files and the records in each are in time order: nothing later is in the range.
      finished_ = true;
      file_.reset();
      break;
    }
    end_of_last_ = record.end_unix_ms();
    rows.push_back(record);
  }
  return rows;
}

}  // namespace tiltgate::monitoring

