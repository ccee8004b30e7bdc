// The disk the long record takes (docs/monitoring.md, "The long record"), for `tiltgate check`
// to show before a gateway runs with it. Pure.
//
// A sensor's record is at most keep_days + 1 day files (the days kept and the day being
// written), each at most a header and one record per interval of the day, taken up in whole
// filesystem blocks:
//
//   per file    = round_up(16 + 72 x ceil(86400 / interval_s), 4096)
//   per sensor  = (keep_days + 1) x per file
//
// 60 s, 91 days: round_up(16 + 72 x 1440, 4096) = 106,496 bytes a day, 9.8 MB a sensor.
#pragma once

#include <cstdint>
#include <string>

namespace tiltgate::monitoring {

// The filesystem block a file is counted in (ext4's and most SD cards' 4 KiB).
inline constexpr std::uint64_t kDiskBlockBytes = 4096;

// The bytes at most one day's file of the record takes on disk at `interval_s` (at least 1).
std::uint64_t record_day_file_bytes(std::uint32_t interval_s);
// The bytes at most one sensor's record takes on disk.
std::uint64_t record_bytes_per_sensor(std::uint32_t keep_days, std::uint32_t interval_s);
// ... and `sensors` sensors' records.
std::uint64_t record_bytes_total(std::uint64_t sensors, std::uint32_t keep_days,
                                 std::uint32_t interval_s);

// The line `tiltgate check` prints: "long record: 12 sensors x 91 days at 60 s: 117.6 MB"
// (decimal units: kB, MB, GB, one decimal).
std::string record_budget_text(std::uint64_t sensors, std::uint32_t keep_days,
                               std::uint32_t interval_s);

// "117.6 MB" for 117,571,584 bytes; "512 bytes" below a kilobyte.
std::string disk_bytes_text(std::uint64_t bytes);

}  // namespace tiltgate::monitoring
