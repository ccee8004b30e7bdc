// What the commissioning commands' tests look for in a command's output.
#pragma once

#include <sstream>
#include <string>

namespace tiltgate::test {

// Whether `text` contains `part` anywhere.
inline bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// Whether one whole line of `out` is `line`.
inline bool has_line(const std::string& out, const std::string& line) {
  std::istringstream in(out);
  for (std::string l; std::getline(in, l);)
    if (l == line) return true;
  return false;
}

}  // namespace tiltgate::test
