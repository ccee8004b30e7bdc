// A demo sensor's own family keys (driver/family_commands.h, DemoSensor): the files they name
// are written into the demo's private folder, and the keys naming them go into the demo's
// configuration file, which the loader reads as any other, so the demo's sensors get what a
// configured sensor gets, defaults included.
#pragma once

#include <filesystem>
#include <string>

#include "driver/expected.h"
#include "driver/family_commands.h"  // DemoSensor

namespace tiltgate {

// A fresh folder under the system's temporary directory, removed with everything in it when
// the object goes.
class DemoFolder {
 public:
  static Expected<DemoFolder, std::string> create();
  DemoFolder(DemoFolder&& other) noexcept : path_(std::move(other.path_)) { other.path_.clear(); }
  DemoFolder& operator=(DemoFolder&&) = delete;
  DemoFolder(const DemoFolder&) = delete;
  ~DemoFolder();
  const std::filesystem::path& path() const { return path_; }

 private:
  explicit DemoFolder(std::filesystem::path path) : path_(std::move(path)) {}
  std::filesystem::path path_;
};

// Writes `contents` as the file `path` (the demo's configuration, a sensor's file).
Expected<Done, std::string> write_demo_file(const std::filesystem::path& path,
                                            std::string_view contents);

// Writes the sensor's files into `folder` (a sub-folder per sensor) and returns the keys that
// name them, as `key = "path"` lines of its [[sensor]] table; the error names the sensor.
Expected<std::string, std::string> demo_sensor_keys(const DemoSensor& sensor,
                                                    const std::filesystem::path& folder);

}  // namespace tiltgate
