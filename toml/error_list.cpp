#include "toml/error_list.h"

#include <algorithm>

namespace tiltgate::toml_input {

void ErrorList::add(Place where, std::string key, std::string message) {
  errors_.push_back(
      FileError{file_, where.line, where.column, std::move(key), std::move(message)});
}

FileErrors ErrorList::take() {
  auto order = [](const FileError& e) {
    // Errors without a line (a missing section) read best after the located ones.
    return std::pair(e.line == 0 ? 1 : 0, std::pair(e.line, e.column));
  };
  std::stable_sort(errors_.begin(), errors_.end(),
                   [&](const FileError& a, const FileError& b) { return order(a) < order(b); });
  // One map file checked for two models reports the problems they share twice.
  auto same = [](const FileError& a, const FileError& b) {
    return a.line == b.line && a.column == b.column && a.key == b.key && a.message == b.message;
  };
  errors_.erase(std::unique(errors_.begin(), errors_.end(), same), errors_.end());
  // A profile named by two sensors reports its problems twice.
  for (FileError& error : elsewhere_) {
    const bool seen = std::any_of(errors_.begin(), errors_.end(), [&](const FileError& e) {
      return e.file == error.file && same(e, error);
    });
    if (!seen) errors_.push_back(std::move(error));
  }
  elsewhere_.clear();
  return std::move(errors_);
}

Place Located::at(std::string_view key) const {
  auto found = places_.find(key);
  return found == places_.end() ? header_ : found->second;
}

std::string Located::key_path(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

void Located::report(ErrorList& errors, std::string_view key, std::string message) const {
  errors.add(at(key), key_path(key), std::move(message));
}

}  // namespace tiltgate::toml_input
