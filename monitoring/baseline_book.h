// The baselines set since the configuration (docs/monitoring.md, "Baseline and
// displacement"): from the console or `tiltgate baseline`, kept in <state_dir>/baselines.json
// across restarts, and winning over [[sensor]] baseline until cleared. The file is replaced
// whole at each change (store/whole_file_write.h), so a power cut leaves the old book or the
// new one:
//
//   {"mast": {"x": 0.12, "y": -0.03, "unix_ms": 1796638502250, "by": "console admin"}}
//
// Threads: any (one mutex); changes are rare and small.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "config/config.h"
#include "driver/expected.h"

namespace tiltgate::monitoring {

struct StoredBaseline {
  Baseline baseline;
  std::int64_t unix_ms = 0;  // when it was set
  std::string by;            // who set it, as the audit trail names them

  bool operator==(const StoredBaseline&) const = default;
};

class BaselineBook {
 public:
  // Reads the book in `dir` (none yet: empty). An empty `dir` (no state directory: the demo)
  // keeps the book in memory only. A file that cannot be read or parsed leaves the
  // book empty and says why in load_error(): the configuration's baselines apply meanwhile, and
  // the next change writes a good file.
  explicit BaselineBook(std::filesystem::path dir);

  std::optional<StoredBaseline> find(const std::string& sensor) const;
  // What a sensor starts with: the stored baseline, else the configuration's, else 0, 0.
  Baseline effective(const SensorConfig& sensor) const;
  // Sets (or, with none, clears) the sensor's stored baseline and writes the file.
  Expected<Done, std::string> set(const std::string& sensor, std::optional<StoredBaseline> value);

  const std::optional<std::string>& load_error() const { return load_error_; }
  std::filesystem::path file() const { return dir_ / "baselines.json"; }

 private:
  std::filesystem::path dir_;
  mutable std::mutex mutex_;
  std::map<std::string, StoredBaseline> stored_;
  std::optional<std::string> load_error_;
};

}  // namespace tiltgate::monitoring
