#include "config/map_files.h"

#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "toml/text_file.h"
#include "toml/toml_parse.h"
#include "toml/toml_reader.h"

namespace tiltgate::config {

using toml_input::place_of;
using toml_input::ErrorList;
using toml_input::read_toml_file;
namespace {

struct MapFile {
  explicit MapFile(std::string p) : path(p), errors(std::move(p)) {}

  std::string path;
  std::string open_error;        // why it could not be read; empty when it was
  std::optional<ParsedMap> map;  // when it was read and parsed
  ErrorList errors;
  // Each sensor kind's checks reported once: its model and its own values' names.
  std::set<std::string, std::less<>> checked_kinds;
};

std::string resolve(std::string_view config_path, const std::string& map_file) {
  std::filesystem::path path(map_file);
  if (path.is_relative()) path = std::filesystem::path(config_path).parent_path() / path;
  return path.lexically_normal().string();
}

std::unique_ptr<MapFile> load(const std::string& path, FamilyList families) {
  auto file = std::make_unique<MapFile>(path);
  auto text = read_toml_file(path);
  if (!text) {
    file->open_error = text.error();
    return file;
  }
  auto root = toml_input::parse_toml(*text, path);
  if (!root) {
    file->errors.add(root.error().where, "", std::move(root.error().description));
    return file;
  }
  file->map = read_map(*root, "", file->errors, families);
  return file;
}

class MapFiles {
 public:
  explicit MapFiles(FamilyList families) : families_(families) {}

  MapFile& get(const std::string& path) {
    for (auto& file : files_)
      if (file->path == path) return *file;
    files_.push_back(load(path, families_));
    return *files_.back();
  }

  ConfigErrors take_errors() {
    ConfigErrors all;
    for (auto& file : files_) {
      ConfigErrors errors = file->errors.take();
      all.insert(all.end(), errors.begin(), errors.end());
    }
    return all;
  }

 private:
  FamilyList families_;
  std::vector<std::unique_ptr<MapFile>> files_;
};

// The model a sensor's map is checked for: "" when the model is itself in error, so that the
// map's own problems are still reported in the same run.
std::string checked_model(const ParsedSensor& sensor) {
  return sensor.where.valid("model") ? sensor.config.model : std::string();
}

const std::vector<DeviceValue>& device_values(const ParsedSensor& sensor) {
  return sensor.config.family_options.device_values();
}

// What the checks of a map depend on: the model and the sensor's own values.
std::string sensor_kind(const ParsedSensor& sensor) {
  std::string kind = checked_model(sensor);
  for (const DeviceValue& value : device_values(sensor))
    kind += fmt::format("\n{}{}", value.name, value.writable ? " (writable)" : "");
  return kind;
}

void use_file(ParsedSensor& sensor, std::string_view config_path, MapFiles& files,
              ErrorList& errors, FamilyList families) {
  const std::string path = resolve(config_path, sensor.map_file);
  MapFile& file = files.get(path);
  if (!file.open_error.empty())
    return sensor.where.report(
        errors, "map", fmt::format("\"{}\" ({}) {}", sensor.map_file, path, file.open_error));
  if (!file.map) return;  // its syntax error is reported in the file
  if (file.checked_kinds.insert(sensor_kind(sensor)).second)
    check_map(*file.map, checked_model(sensor), device_values(sensor), file.errors, families);
  sensor.config.map = file.map->definition;
  sensor.config.map_file = path;
}

}  // namespace

ConfigErrors load_sensor_maps(std::vector<ParsedSensor>& sensors, std::string_view config_path,
                              ErrorList& errors, FamilyList families) {
  MapFiles files(families);
  for (ParsedSensor& sensor : sensors) {
    if (sensor.inline_map) {
      check_map(*sensor.inline_map, checked_model(sensor), device_values(sensor), errors, families);
      sensor.config.map = sensor.inline_map->definition;
    } else if (!sensor.map_file.empty()) {
      use_file(sensor, config_path, files, errors, families);
    }
  }
  return files.take_errors();
}

}  // namespace tiltgate::config
