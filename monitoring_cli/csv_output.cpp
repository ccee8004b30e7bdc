#include "monitoring_cli/csv_output.h"

#include <fmt/format.h>

#include <iostream>

namespace tiltgate {

std::ostream* open_csv_output(const std::string& path, std::ofstream& file,
                              std::string_view command) {
  if (path == "-") return &std::cout;
  file.open(path, std::ios::binary | std::ios::trunc);
  if (file) return &file;
  std::cerr << fmt::format("tiltgate {}: cannot write {}\n", command, path);
  return nullptr;
}

}  // namespace tiltgate
