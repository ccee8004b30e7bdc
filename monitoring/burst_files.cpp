#include "monitoring/burst_files.h"

#include <fcntl.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <system_error>

#include "monitoring/long_record.h"
#include "monitoring/utc_time.h"
#include "store/file_io.h"

namespace tiltgate::monitoring {

namespace {

constexpr std::string_view kCsvSuffix = ".csv";

// The shortest text that reads back the same double; empty for none.
std::string cell(double value) {
  if (std::isnan(value) || std::isinf(value)) return {};
  return fmt::format("{}", value);
}

const char* phase_name(BurstPhase phase) {
  switch (phase) {
    case BurstPhase::pre: return "pre";
    case BurstPhase::trigger: return "trigger";
    case BurstPhase::burst: break;
  }
  return "burst";
}

// "2026-12-07T10-15-02.250Z" back to Unix ms; none for anything else.
std::optional<std::int64_t> id_time(std::string_view id) {
  if (id.size() != 24 || id[10] != 'T' || id[13] != '-' || id[16] != '-' || id[19] != '.' ||
      id[23] != 'Z')
    return std::nullopt;
  std::string text(id);
  text[13] = ':';
  text[16] = ':';
  for (std::size_t i : {11u, 12u, 14u, 15u, 17u, 18u, 20u, 21u, 22u})
    if (text[i] < '0' || text[i] > '9') return std::nullopt;
  const auto day = parse_utc_date(text.substr(0, 10));
  if (!day) return std::nullopt;
  const auto number = [&](std::size_t at, std::size_t n) { return std::stoll(text.substr(at, n)); };
  const std::int64_t hours = number(11, 2), minutes = number(14, 2), seconds = number(17, 2);
  if (hours > 23 || minutes > 59 || seconds > 59) return std::nullopt;
  return day_start_unix_ms(*day) + ((hours * 60 + minutes) * 60 + seconds) * 1000 + number(20, 3);
}

}  // namespace

std::string burst_id(std::int64_t unix_ms) {
  std::string id = utc_timestamp(unix_ms);  // 2026-12-07T10:15:02.250Z
  std::replace(id.begin(), id.end(), ':', '-');
  return id;
}

std::filesystem::path burst_directory(const std::filesystem::path& state_dir,
                                      std::string_view sensor) {
  return state_dir / "bursts" / sensor_folder_name(sensor);
}

std::optional<std::filesystem::path> burst_path(const std::filesystem::path& dir,
                                                std::string_view id) {
  if (!id_time(id)) return std::nullopt;
  return dir / (std::string(id) + std::string(kCsvSuffix));
}

std::string burst_csv_header() {
  return "time,unix_ms,phase,x,y,tilt,relative_x,relative_y,displacement_mm,temperature,alarms,"
         "clock_synchronised\r\n";
}

std::string burst_csv_rows(const std::vector<FedSample>& samples, BurstPhase phase) {
  std::string out;
  for (const FedSample& s : samples)
    out += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\r\n", utc_timestamp(s.unix_ms),
                       s.unix_ms, phase_name(phase), cell(s.x), cell(s.y), cell(s.tilt),
                       cell(s.relative_x), cell(s.relative_y), cell(s.displacement_mm),
                       cell(s.temperature_c), s.alarms, s.clock_synchronised ? 1 : 0);
  return out;
}

Expected<Done, std::string> append_burst(const std::filesystem::path& path,
                                         std::string_view text) {
  std::error_code ignored;
  const bool made = !std::filesystem::exists(path, ignored);
  std::filesystem::create_directories(path.parent_path(), ignored);
  auto fd = store::open_file(path, O_WRONLY | O_CREAT | O_APPEND);
  if (!fd) return Unexpected(fd.error());
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(text.data());
  if (auto written = store::write_all(fd->get(), {bytes, text.size()}, path); !written)
    return written;
  if (auto synced = store::sync_file(fd->get(), path); !synced) return synced;
  if (made) return store::sync_directory(path.parent_path());
  return Done{};
}

std::vector<BurstFile> list_bursts(const std::filesystem::path& dir) {
  std::vector<BurstFile> found;
  std::error_code error;
  for (std::filesystem::directory_iterator it(dir, error), end; !error && it != end;
       it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (!name.ends_with(kCsvSuffix)) continue;
    const std::string id = name.substr(0, name.size() - kCsvSuffix.size());
    const auto time = id_time(id);
    if (!time) continue;
    std::error_code size_error;
    const auto bytes = std::filesystem::file_size(it->path(), size_error);
    found.push_back({id, *time, size_error ? 0 : bytes});
  }
  std::sort(found.begin(), found.end(),
            [](const BurstFile& a, const BurstFile& b) { return a.unix_ms > b.unix_ms; });
  return found;
}

std::size_t remove_old_bursts(const std::filesystem::path& dir, std::size_t keep) {
  const std::vector<BurstFile> bursts = list_bursts(dir);
  std::size_t removed = 0;
  for (std::size_t i = keep; i < bursts.size(); ++i) {
    std::error_code ignored;
    if (std::filesystem::remove(dir / (bursts[i].id + std::string(kCsvSuffix)), ignored))
      ++removed;
  }
  return removed;
}

}  // namespace tiltgate::monitoring
