#include "app/demo_sensor_keys.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <optional>
#include <system_error>
#include <vector>

namespace tiltgate {

namespace {

// The family's keys as a demo sensor gives them: only its files; every other key is absent,
// so the family applies its defaults. Problems are collected rather than located in a file.
class DemoKeyReader final : public SensorKeyReader {
 public:
  DemoKeyReader(const DemoSensor& sensor, const std::filesystem::path& folder, FamilyList families)
      : sensor_(sensor), folder_(folder), families_(families) {}
  std::optional<double> number(std::string_view) override { return std::nullopt; }
  std::optional<bool> boolean(std::string_view) override { return std::nullopt; }
  std::optional<std::string> file_path(std::string_view key) override {
    for (const DemoFile& file : sensor_.files)
      if (file.key == key) return (folder_ / file.file_name).string();
    return std::nullopt;
  }
  void error(std::string_view key, std::string message) override {
    problems_.push_back(fmt::format("{}: {}", key, message));
  }
  std::vector<std::string_view> setting_names() const override {
    return model_setting_names(families_);
  }
  void file_errors(FileErrors errors) override {
    for (const FileError& e : errors)
      problems_.push_back(fmt::format("{}:{}: {}: {}", e.file, e.line, e.key, e.message));
  }
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  const DemoSensor& sensor_;
  const std::filesystem::path& folder_;
  FamilyList families_;
  std::vector<std::string> problems_;
};

Expected<Done, std::string> write_file(const std::filesystem::path& path,
                                       std::string_view contents) {
  std::ofstream out(path, std::ios::binary);
  out.write(contents.data(), std::streamsize(contents.size()));
  out.close();
  if (!out) return Unexpected{fmt::format("cannot write {}", path.string())};
  return Done{};
}

}  // namespace

Expected<DemoFolder, std::string> DemoFolder::create() {
  std::error_code ec;
  std::filesystem::path base = std::filesystem::temp_directory_path(ec);
  if (ec) base = "/tmp";
  std::string name = (base / "tiltgate-demo-XXXXXX").string();
  if (::mkdtemp(name.data()) == nullptr)
    return Unexpected{fmt::format("cannot create a folder {}: {}", name, std::strerror(errno))};
  return DemoFolder(std::filesystem::path(name));
}

DemoFolder::~DemoFolder() {
  if (path_.empty()) return;
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

Expected<FamilyOptions, std::string> demo_sensor_options(FamilyList families,
                                                         const FamilyDescriptor& family,
                                                         const DemoSensor& sensor,
                                                         const std::filesystem::path& folder) {
  const std::filesystem::path own = folder / std::string(sensor.name);
  if (!sensor.files.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(own, ec);
    if (ec) return Unexpected{fmt::format("cannot create {}: {}", own.string(), ec.message())};
  }
  for (const DemoFile& file : sensor.files)
    if (auto written = write_file(own / file.file_name, file.contents); !written)
      return Unexpected{written.error()};
  DemoKeyReader reader(sensor, own, families);
  FamilyOptions options;
  family.read_sensor_keys(reader, options);
  if (!reader.problems().empty())
    return Unexpected{fmt::format("demo sensor {}: {}", sensor.name,
                                  fmt::join(reader.problems(), "; "))};
  return options;
}

}  // namespace tiltgate
