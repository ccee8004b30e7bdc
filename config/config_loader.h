// Loads a tiltgate TOML configuration and validates all of it before anything starts, so a
// commissioning mistake is reported up front, compiler style, instead of at 3 a.m. on a bus.
// Every key, default and range is listed in docs/configuration.md.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "config/config.h"
#include "driver/expected.h"
#include "driver/family.h"

namespace tiltgate {

struct ConfigError {
  std::string file;
  int line = 0;         // 1-based; 0 when the problem has no one place (unreadable file)
  int column = 0;       // 1-based
  std::string key;      // "server.port", "bus[0].baud", "sensor[2].unit_id"; empty for syntax
  std::string message;  // what is wrong and what is expected

  // "FILE:LINE:COL: KEY: message", or "FILE: KEY: message" when there is no line.
  std::string to_string() const;
};

using ConfigErrors = std::vector<ConfigError>;

// Every problem in the file, ordered by line; a TOML syntax error is reported alone.
// Protocols, models and their keys are those of `families`.
Expected<Config, ConfigErrors> load_config_file(const std::string& path,
                                                FamilyList families = registered_families());
// The same from text in memory; `source_name` stands for the file name in errors and in
// Config::path.
Expected<Config, ConfigErrors> load_config_string(std::string_view text,
                                                  std::string_view source_name,
                                                  FamilyList families = registered_families());

}  // namespace tiltgate
