// Collecting configuration errors, and remembering where each key was written so that checks
// made after reading (duplicates, a sensor against its bus) still point at the right line.
#pragma once

#include <map>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "driver/file_error.h"

namespace tiltgate::toml_input {

struct Place {
  int line = 0;
  int column = 0;
};

// The keys each kind of table accepts, as its reader asks for them, by the table's path without
// indices: "sensor" -> {"name", "bus", ...}, "sensor.map.point" -> {"name", "table", ...}.
using AcceptedKeys = std::map<std::string, std::set<std::string>, std::less<>>;

class ErrorList {
 public:
  explicit ErrorList(std::string file) : file_(std::move(file)) {}

  // Has every table read on this list record the keys it accepts into `keys` (see
  // config/accepted_keys.h); nullptr, the default, records nothing.
  void record_accepted_keys(AcceptedKeys* keys) { accepted_keys_ = keys; }
  AcceptedKeys* accepted_keys() const { return accepted_keys_; }

  void add(Place where, std::string key, std::string message);
  // An error in another file (a device profile): kept after this file's own, in given order.
  void add_elsewhere(FileError error) { elsewhere_.push_back(std::move(error)); }
  const std::string& file() const { return file_; }
  bool empty() const { return errors_.empty() && elsewhere_.empty(); }
  std::size_t size() const { return errors_.size() + elsewhere_.size(); }
  // The errors ordered by place; those without a line come last.
  FileErrors take();

 private:
  std::string file_;
  FileErrors errors_;
  FileErrors elsewhere_;
  AcceptedKeys* accepted_keys_ = nullptr;
};

// Where one table ([server], one [[bus]], one [[sensor]]) and its keys were written.
class Located {
 public:
  Located(std::string path, Place header) : path_(std::move(path)), header_(header) {}

  void set(std::string_view key, Place where) { places_[std::string(key)] = where; }
  void mark_valid(std::string_view key) { valid_.insert(std::string(key)); }

  // Present, of the right type and in range: later checks may rely on its value.
  bool valid(std::string_view key) const { return valid_.find(key) != valid_.end(); }
  // Valid, or absent so that its default holds.
  bool usable(std::string_view key) const {
    return valid(key) || places_.find(key) == places_.end();
  }
  // The key's place, or the table header's when the key is absent.
  Place at(std::string_view key) const;
  Place header() const { return header_; }
  const std::string& path() const { return path_; }
  // "sensor[2].unit_id"
  std::string key_path(std::string_view key) const;
  void report(ErrorList& errors, std::string_view key, std::string message) const;

 private:
  std::string path_;
  Place header_;
  std::map<std::string, Place, std::less<>> places_;
  std::set<std::string, std::less<>> valid_;
};

}  // namespace tiltgate::toml_input
