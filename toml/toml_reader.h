// Typed, range-checked reads from one TOML table. Each read reports its own error (wrong
// type, out of range, missing) and returns nothing, so the caller simply reads on and every
// problem in the file is found in one pass.
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "driver/closest_name.h"

#include "toml/error_list.h"

namespace tiltgate::toml_input {

enum class Presence { optional, required };

class TableReader {
 public:
  // `path` names the table in messages: "server", "bus[0]".
  TableReader(const toml::table& table, std::string path, ErrorList& errors);

  std::optional<std::int64_t> integer(std::string_view key, std::int64_t min, std::int64_t max,
                                      Presence presence = Presence::optional);
  // An integer or a float, finite (or NaN too, when allow_nan).
  std::optional<double> number(std::string_view key, Presence presence = Presence::optional,
                               bool allow_nan = false);
  // A number in min..max.
  std::optional<double> number_in(std::string_view key, double min, double max,
                                  Presence presence = Presence::optional);
  std::optional<bool> boolean(std::string_view key, Presence presence = Presence::optional);
  std::optional<std::string> string(std::string_view key, Presence presence = Presence::optional);
  // A string that must be one of `allowed`.
  std::optional<std::string> choice(std::string_view key,
                                    std::initializer_list<std::string_view> allowed,
                                    Presence presence = Presence::optional);
  std::optional<std::string> choice(std::string_view key, std::span<const std::string_view> allowed,
                                    Presence presence = Presence::optional);
  // An array of strings.
  std::optional<std::vector<std::string>> strings(std::string_view key,
                                                  Presence presence = Presence::optional);
  // An array of integers, each in min..max.
  std::optional<std::vector<std::int64_t>> integers(std::string_view key, std::int64_t min,
                                                    std::int64_t max,
                                                    Presence presence = Presence::optional);
  // A table: an inline table or a [parent.key] sub-table, which toml++ gives alike.
  const toml::table* table(std::string_view key, Presence presence = Presence::optional);
  // Any node, for a key whose type selects its meaning; the caller checks it and calls
  // accept() when it is valid.
  const toml::node* node(std::string_view key);
  void accept(std::string_view key) { located_.mark_valid(key); }

  bool has(std::string_view key) const { return table_.contains(key); }
  // A problem with a value that read fine on its own (a check against another key).
  void error(std::string_view key, std::string message);
  // Every key that no read above asked for is an error, with a "did you mean" when a known
  // key is close. Call after the last read.
  void reject_unknown_keys();

  const Located& located() const { return located_; }

 private:
  // The node if present and of type `expected`; reports a missing required key or a wrong type.
  const toml::node* find(std::string_view key, toml::node_type expected, Presence presence,
                         std::string_view expectation);
  const toml::node* find_any(std::string_view key, Presence presence, std::string_view expectation);

  const toml::table& table_;
  ErrorList& errors_;
  Located located_;
  std::vector<std::string> asked_;
};

// Where a node was written (toml++ counts lines and columns from 1, as do compilers).
Place place_of(const toml::source_region& region);
// "an integer", "a string": for "expected X, got Y".
std::string_view type_name(toml::node_type type);
// The known key a misspelt one most likely meant (driver/closest_name.h).
inline std::string closest_key(std::string_view unknown, std::span<const std::string> known) {
  return closest_name(unknown, known);
}

// Bounds for TableReader::integer() when the range is checked later (it depends on another
// table, e.g. a sensor's address on its bus's protocol).
inline constexpr std::int64_t kAnyInteger = std::numeric_limits<std::int64_t>::min();
inline constexpr std::int64_t kAnyIntegerMax = std::numeric_limits<std::int64_t>::max();

// Names appear in logs, metrics and on the command line: keeps them to a safe alphabet
// (reported at `key` otherwise).
void check_name(TableReader& in, std::string_view key, const std::string& name);

}  // namespace tiltgate::toml_input
