// A demo sensor's own family keys (driver/bus_simulator.h, DemoSensor): the files they name are
// written into a private folder, and the family reads its keys as from a configuration, so
// the demo's sensors get what a configured sensor gets, defaults included.
#pragma once

#include <filesystem>
#include <string>

#include "driver/expected.h"
#include "driver/family.h"
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

// Writes the sensor's files into `folder` (a sub-folder per sensor) and has `family`, one of
// `families`, read its keys; the error names the sensor and the problem.
Expected<FamilyOptions, std::string> demo_sensor_options(FamilyList families,
                                                         const FamilyDescriptor& family,
                                                         const DemoSensor& sensor,
                                                         const std::filesystem::path& folder);

}  // namespace tiltgate
