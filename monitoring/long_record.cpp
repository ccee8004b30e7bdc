#include "monitoring/long_record.h"

#include <algorithm>
#include <system_error>

#include "monitoring/record_format.h"
#include "monitoring/utc_time.h"

namespace tiltgate::monitoring {

std::string sensor_folder_name(std::string_view sensor) {
  std::string folder(sensor);
  if (!folder.empty() && folder.front() == '.') folder.replace(0, 1, "%2E");
  return folder;
}

std::filesystem::path record_directory(const std::filesystem::path& state_dir,
                                       std::string_view sensor) {
  return state_dir / "record" / sensor_folder_name(sensor);
}

LongRecord::LongRecord(std::filesystem::path dir, LongRecordOptions options)
    : dir_(std::move(dir)), options_(options) {}

LongRecord LongRecord::open(std::filesystem::path dir, LongRecordOptions options) {
  LongRecord record(std::move(dir), options);
  record.attach();
  return record;
}

LongRecord::~LongRecord() {
  // A moved-from record holds no descriptor: nothing to sync.
  if (!writer_.valid()) return;
  if (unsynced_ > 0) (void)store::sync_file(writer_.get(), day_path(writer_day_));
  if (names_unsynced_) (void)store::sync_directory(dir_);
}

LongRecord::Appended LongRecord::append(const IntervalRecord& interval) {
  if (accepted_until_ && interval.start_unix_ms < *accepted_until_) {
    ++behind_;
    if (!behind_said_) {
      behind_said_ = true;
      notices_.push_back({true, "long record " + dir_.string() + ": the interval of " +
                                    utc_timestamp(interval.start_unix_ms) +
                                    " is refused, and any other before " +
                                    utc_timestamp(*accepted_until_) +
                                    ", where the record already ends (a clock stepped back?)"});
    }
    return Appended::behind;
  }
  behind_said_ = false;
  accepted_until_ = interval.end_unix_ms();
  held_.push_back(interval);
  if (held_.size() > std::max<std::size_t>(options_.hold_max, 1)) {
    held_.pop_front();
    ++lost_;
    if (++fault_lost_ == 1)
      notices_.push_back({true, "long record " + dir_.string() + ": " +
                                    std::to_string(held_.size()) +
                                    " intervals held in memory: the oldest are lost from now on"});
  }
  if (write_held()) note_recovery();
  return held_.empty() ? Appended::written : Appended::held;
}

bool LongRecord::write_held() {
  if (!attached_ && !attach()) return false;
  while (!held_.empty()) {
    auto written = write(held_.front());
    if (!written) {
      note_fault(written.error());
      return false;
    }
    held_.pop_front();
    if (options_.sync_every > 0 && unsynced_ >= options_.sync_every) {
      if (auto synced = sync_files(); !synced) {
        note_fault(synced.error());
        return false;
      }
    }
  }
  return true;
}

Expected<Done, std::string> LongRecord::write(const IntervalRecord& interval) {
  // Held before the directory could be read, it may start before what the disk already holds.
  if (disk_end_ && interval.start_unix_ms < *disk_end_) {
    ++behind_;
    return Done{};
  }
  const std::int64_t day = utc_day(interval.start_unix_ms);
  if (!writer_.valid() || writer_day_ != day) {
    // The day left behind is synced now: its descriptor is about to go.
    if (writer_.valid() && unsynced_ > 0) {
      // A failure here is noted, not waited on: the next day's records go on regardless.
      if (auto synced = sync_files(); !synced) note_fault(synced.error());
    }
    writer_.reset();
    if (auto opened = open_day(day); !opened) return opened;
  }
  const RecordBytes bytes = encode_record(interval);
  if (auto written = store::write_all(writer_.get(), bytes, day_path(day)); !written) {
    // Part of it may have reached the file: reopening the day cuts that off.
    writer_.reset();
    return written;
  }
  ++appended_;
  disk_end_ = interval.end_unix_ms();
  ++unsynced_;
  return Done{};
}

Expected<Done, std::string> LongRecord::sync_files() {
  if (writer_.valid() && unsynced_ > 0) {
    if (auto synced = store::sync_file(writer_.get(), day_path(writer_day_)); !synced)
      return synced;
    unsynced_ = 0;
  }
  if (names_unsynced_) {
    if (auto synced = store::sync_directory(dir_); !synced) return synced;
    names_unsynced_ = false;
  }
  return Done{};
}

void LongRecord::sync() {
  if (!write_held()) return;  // the fault is noted
  if (auto synced = sync_files(); !synced) {
    note_fault(synced.error());
    return;
  }
  note_recovery();
}

std::size_t LongRecord::remove_expired(std::int64_t now_unix_ms) {
  if (!attached_ && !attach()) return 0;
  std::int64_t newest = utc_day(now_unix_ms);
  if (accepted_until_) newest = std::min(newest, utc_day(*accepted_until_ - 1));
  const std::int64_t first_kept = newest - options_.keep_days;
  std::error_code ec;
  std::vector<std::filesystem::path> expired;
  for (std::filesystem::directory_iterator it(dir_, ec), end; !ec && it != end; it.increment(ec)) {
    const auto name = parse_record_file_name(it->path().filename().string());
    if (name && name->day < first_kept) expired.push_back(it->path());
  }
  if (ec) {
    note_fault("cannot list " + dir_.string() + ": " + ec.message());
    return 0;
  }
  if (writer_.valid() && writer_day_ < first_kept) {
    (void)sync_files();
    writer_.reset();
  }
  std::size_t removed = 0;
  for (const auto& path : expired) {
    const bool gone = std::filesystem::remove(path, ec);
    if (ec) {
      note_fault("cannot remove " + path.string() + ": " + ec.message());
      continue;
    }
    if (!gone) continue;  // removed meanwhile by someone else
    ++removed;
    names_unsynced_ = true;
  }
  removed_files_ += removed;
  return removed;
}

std::vector<RecordNotice> LongRecord::take_notices() {
  std::vector<RecordNotice> taken;
  taken.swap(notices_);
  return taken;
}

void LongRecord::note_fault(const std::string& error) {
  ++disk_failures_;
  if (!fault_)
    notices_.push_back({true, "long record " + dir_.string() + ": " + error +
                                  "; intervals are held in memory (at most " +
                                  std::to_string(options_.hold_max) +
                                  ") and written once the disk takes them"});
  fault_ = error;
}

void LongRecord::note_recovery() {
  if (!fault_) return;
  std::string text = "long record " + dir_.string() + ": the disk takes intervals again";
  if (fault_lost_ > 0)
    text += "; " + std::to_string(fault_lost_) + " intervals were lost while it refused";
  notices_.push_back({false, text});
  fault_.reset();
  fault_lost_ = 0;
}

}  // namespace tiltgate::monitoring
