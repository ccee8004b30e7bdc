#include "driver/simulator_command.h"

#include <cctype>
#include <charconv>
#include <cmath>

namespace tiltgate {

namespace {

// The blank-separated words of `line`.
std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t at = 0;
  while (at < line.size()) {
    while (at < line.size() && std::isspace(static_cast<unsigned char>(line[at]))) ++at;
    std::size_t end = at;
    while (end < line.size() && !std::isspace(static_cast<unsigned char>(line[end]))) ++end;
    if (end > at) words.push_back(line.substr(at, end - at));
    at = end;
  }
  return words;
}

// The whole word as a number of type T, or false.
template <class T>
bool whole_number(std::string_view word, T& value) {
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  return ec == std::errc{} && end == word.data() + word.size();
}

}  // namespace

Expected<SimulatorCommand, std::string> parse_simulator_command(std::string_view line) {
  const std::vector<std::string_view> words = words_of(line);
  if (words.empty()) return Unexpected{std::string("empty command")};
  SimulatorCommand command;
  command.verb = std::string(words[0]);
  if (words.size() < 2) return Unexpected{"\"" + command.verb + "\" needs a sensor address"};
  if (!whole_number(words[1], command.address)) {
    return Unexpected{"\"" + std::string(words[1]) + "\" is not a sensor address"};
  }
  for (std::size_t i = 2; i < words.size(); ++i) {
    double value = 0;
    if (!whole_number(words[i], value) || !std::isfinite(value)) {
      return Unexpected{"\"" + std::string(words[i]) + "\" is not a number"};
    }
    command.values.push_back(value);
  }
  return command;
}

}  // namespace tiltgate
