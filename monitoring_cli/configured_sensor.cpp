#include "monitoring_cli/configured_sensor.h"

#include <fmt/format.h>

#include <iostream>

#include "config/config_loader.h"

namespace tiltgate {

std::optional<ConfiguredSensor> load_configured_sensor(std::string_view command,
                                                       const std::string& config_path,
                                                       const std::string& sensor,
                                                       FamilyList families) {
  auto loaded = load_config_file(config_path, families);
  if (!loaded) {
    std::cerr << fmt::format("tiltgate {}: {} is not a configuration the gateway would run:",
                             command, config_path);
    for (const ConfigError& e : loaded.error()) std::cerr << "\n  " << e.to_string();
    std::cerr << "\n";
    return std::nullopt;
  }
  for (const SensorConfig& s : loaded->sensors)
    if (s.name == sensor) return ConfiguredSensor{std::move(*loaded), s};
  std::cerr << fmt::format("tiltgate {}: {} has no sensor \"{}\"\n", command, config_path, sensor);
  return std::nullopt;
}

}  // namespace tiltgate
