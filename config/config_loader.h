// Loads a tiltgate TOML configuration and validates all of it before anything starts, so a
// commissioning mistake is reported up front, compiler style, instead of at 3 a.m. on a bus.
// Every key, default and range is listed in docs/configuration.md.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "config/config.h"
#include "driver/expected.h"
#include "driver/file_error.h"
#include "driver/family.h"

namespace tiltgate {

// A problem in the configuration or a file it names, at its place.
using ConfigError = FileError;
using ConfigErrors = FileErrors;

// Every problem in the file, ordered by line; a TOML syntax error is reported alone.
// Protocols, models and their keys are those of `families`.
Expected<Config, ConfigErrors> load_config_file(const std::string& path,
                                                FamilyList families);
// The same from text in memory; `source_name` stands for the file name in errors and in
// Config::path.
Expected<Config, ConfigErrors> load_config_string(std::string_view text,
                                                  std::string_view source_name,
                                                  FamilyList families);

}  // namespace tiltgate
