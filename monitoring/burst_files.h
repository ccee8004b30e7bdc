// Burst records on disk (docs/monitoring.md, "Bursts"): one CSV file per burst in
// <state_dir>/bursts/SENSOR/, named by the trigger's UTC time (2026-12-07T10-15-02.250Z.csv,
// no colons, so any file system takes it), written as the burst goes: the samples before the
// trigger first, then each batch of the burst's. At most kBurstsKept per sensor: the oldest
// goes when a new one starts.
//
//   time,unix_ms,phase,x,y,tilt,relative_x,relative_y,displacement_mm,temperature,alarms,
//   clock_synchronised
//   2026-12-07T10:15:01.250Z,1796638501250,pre,1.9985,0.0012,1.9985,...
//
// `phase` is `pre` for the samples before the trigger, `trigger` for the one that started it,
// `burst` after. Each append is one write(2) and an fdatasync: a power cut loses at most the
// batch being written.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "line_scheduling/sensor_feed.h"

namespace tiltgate::monitoring {

inline constexpr std::size_t kBurstsKept = 100;

struct BurstFile {
  std::string id;             // the file name without ".csv"
  std::int64_t unix_ms = 0;   // the trigger's time
  std::uint64_t bytes = 0;
};

// Where a sensor's bursts live: `<state_dir>/bursts/<sensor>/` (the folder named as the long
// record's, monitoring/long_record.h sensor_folder_name()).
std::filesystem::path burst_directory(const std::filesystem::path& state_dir,
                                      std::string_view sensor);

std::string burst_id(std::int64_t unix_ms);
// The id's file in `dir`, none for text that is no burst id (a path, "..").
std::optional<std::filesystem::path> burst_path(const std::filesystem::path& dir,
                                                std::string_view id);

std::string burst_csv_header();
enum class BurstPhase { pre, trigger, burst };
std::string burst_csv_rows(const std::vector<FedSample>& samples, BurstPhase phase);

// Appends `text` to `path` (made when missing), synced.
Expected<Done, std::string> append_burst(const std::filesystem::path& path, std::string_view text);
// The bursts in `dir`, newest first.
std::vector<BurstFile> list_bursts(const std::filesystem::path& dir);
// Deletes the oldest beyond `keep`; how many.
std::size_t remove_old_bursts(const std::filesystem::path& dir, std::size_t keep);

}  // namespace tiltgate::monitoring
