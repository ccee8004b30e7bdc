#include "app/demo_sensor_keys.h"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <system_error>

#include "toml/toml_string.h"

namespace tiltgate {

Expected<Done, std::string> write_demo_file(const std::filesystem::path& path,
                                            std::string_view contents) {
  std::ofstream out(path, std::ios::binary);
  out.write(contents.data(), std::streamsize(contents.size()));
  out.close();
  if (!out) return Unexpected{fmt::format("cannot write {}", path.string())};
  return Done{};
}

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

Expected<std::string, std::string> demo_sensor_keys(const DemoSensor& sensor,
                                                    const std::filesystem::path& folder) {
  const std::filesystem::path own = folder / std::string(sensor.name);
  if (!sensor.files.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(own, ec);
    if (ec) return Unexpected{fmt::format("demo sensor {}: cannot create {}: {}", sensor.name,
                                          own.string(), ec.message())};
  }
  std::string keys;
  for (const DemoFile& file : sensor.files) {
    const std::filesystem::path path = own / file.file_name;
    if (auto written = write_demo_file(path, file.contents); !written)
      return Unexpected{fmt::format("demo sensor {}: {}", sensor.name, written.error())};
    keys += fmt::format("{} = {}\n", file.key, toml_input::toml_string(path.string()));
  }
  return keys;
}

}  // namespace tiltgate
