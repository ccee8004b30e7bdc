// LongRecord's directory and files (monitoring/long_record.h): reading the directory once it
// can be read, opening a day's file for appending, and the repairs a crash or a damaged disk
// calls for.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <system_error>

#include "monitoring/long_record.h"
#include "monitoring/record_file.h"
#include "monitoring/record_format.h"

namespace tiltgate::monitoring {

std::filesystem::path LongRecord::day_path(std::int64_t day) const {
  return dir_ / record_file_name(day);
}

bool LongRecord::attach() {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) {
    note_fault("cannot create " + dir_.string() + ": " + ec.message());
    return false;
  }
  std::vector<std::int64_t> days;
  for (std::filesystem::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
    const auto name = parse_record_file_name(it->path().filename().string());
    if (name && !name->damaged) days.push_back(name->day);
  }
  if (ec) {
    note_fault("cannot list " + dir_.string() + ": " + ec.message());
    return false;
  }
  std::sort(days.begin(), days.end());
  // Read first, so where the record ends is known even while the disk refuses writes.
  disk_end_ = find_end(days);
  if (disk_end_ && (!accepted_until_ || *accepted_until_ < *disk_end_)) accepted_until_ = disk_end_;
  if (!days.empty()) {
    // Only the newest file is ever appended to: only it can hold what a crash tore.
    if (auto opened = open_day(days.back()); !opened) {
      note_fault(opened.error());
      return false;
    }
  }
  attached_ = true;
  return true;
}

std::optional<std::int64_t> LongRecord::find_end(
    const std::vector<std::int64_t>& days_oldest_first) const {
  for (auto day = days_oldest_first.rbegin(); day != days_oldest_first.rend(); ++day) {
    auto file = RecordFileReader::open(day_path(*day));
    if (!file) continue;
    std::optional<std::int64_t> end;
    for (auto next = file->next(); next && next->slot != RecordFileReader::Slot::end;
         next = file->next())
      if (next->slot == RecordFileReader::Slot::record)
        end = std::max(end.value_or(next->record.end_unix_ms()), next->record.end_unix_ms());
    if (end) return end;
  }
  return std::nullopt;
}

Expected<Done, std::string> LongRecord::open_day(std::int64_t day) {
  const std::filesystem::path path = day_path(day);
  const std::string name = path.filename().string();
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);  // removed by hand since: made again
  if (ec) return Unexpected("cannot create " + dir_.string() + ": " + ec.message());
  // A directory made by hand where the file should be would refuse every append.
  auto cleared = store::clear_way_for_file(path);
  if (!cleared) return Unexpected(cleared.error());
  if (*cleared) repairs_.push_back(**cleared);
  auto fd = store::open_file(path, O_RDWR | O_CREAT | O_APPEND);
  if (!fd) return Unexpected(fd.error());
  struct stat status {};
  if (::fstat(fd->get(), &status) != 0) return Unexpected(store::errno_text("cannot stat", path));
  auto size = static_cast<std::uint64_t>(status.st_size);
  if (size == 0) names_unsynced_ = true;  // a new file: its name is made durable by sync()
  if (size >= kFileHeaderBytes) {
    FileHeader header{};
    auto got = store::read_at(fd->get(), header, 0, path);
    if (!got) return Unexpected(got.error());
    if (!is_file_header(header)) {
      // Not ours, or damaged: kept for whoever looks, out of the record's way.
      std::filesystem::path aside = path;
      aside += kDamagedSuffix;
      std::filesystem::rename(path, aside, ec);
      if (ec) return Unexpected("cannot move aside " + path.string() + ": " + ec.message());
      repairs_.push_back(name + ": its header is not a long record's: moved to " +
                         aside.filename().string());
      names_unsynced_ = true;
      fd = store::open_file(path, O_RDWR | O_CREAT | O_APPEND);
      if (!fd) return Unexpected(fd.error());
      size = 0;
    }
  }
  if (size < kFileHeaderBytes) {
    if (size > 0) {
      if (::ftruncate(fd->get(), 0) != 0)
        return Unexpected(store::errno_text("cannot truncate", path));
      repairs_.push_back(name + ": a header cut short, written again");
    }
    const FileHeader header = file_header();
    if (auto written = store::write_all(fd->get(), header, path); !written) {
      // Neither half a header nor an empty file left behind for each day the disk refused.
      (void)::unlink(path.c_str());
      return written;
    }
  } else if (const std::uint64_t whole = records_end(whole_records(size)); whole != size) {
    if (::ftruncate(fd->get(), static_cast<off_t>(whole)) != 0)
      return Unexpected(store::errno_text("cannot truncate", path));
    if (auto synced = store::sync_file(fd->get(), path); !synced) return synced;
    repairs_.push_back(name + ": cut at byte " + std::to_string(whole) + ": a record cut short");
  }
  writer_ = std::move(*fd);
  writer_day_ = day;
  unsynced_ = 0;
  return Done{};
}

}  // namespace tiltgate::monitoring
