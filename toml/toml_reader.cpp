#include "toml/toml_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace tiltgate::toml_input {

Place place_of(const toml::source_region& region) {
  return Place{int(region.begin.line), int(region.begin.column)};
}

std::string_view type_name(toml::node_type type) {
  switch (type) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a float";
    case toml::node_type::boolean:
      return "a boolean";
    case toml::node_type::date:
      return "a date";
    case toml::node_type::time:
      return "a time";
    case toml::node_type::date_time:
      return "a date-time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

namespace {

std::string join(std::span<const std::string> words, std::string_view separator) {
  std::string out;
  for (const std::string& word : words) out += (out.empty() ? "" : std::string(separator)) + word;
  return out;
}

}  // namespace

TableReader::TableReader(const toml::table& table, std::string path, ErrorList& errors)
    : table_(table), errors_(errors), located_(std::move(path), place_of(table.source())) {
  for (auto&& [key, node] : table) located_.set(key.str(), place_of(key.source()));
}

void TableReader::error(std::string_view key, std::string message) {
  located_.report(errors_, key, std::move(message));
}

const toml::node* TableReader::find_any(std::string_view key, Presence presence,
                                        std::string_view expectation) {
  asked_.emplace_back(key);
  const toml::node* node = table_.get(key);
  if (node == nullptr && presence == Presence::required)
    error(key, fmt::format("required key is missing; expected {}", expectation));
  return node;
}

const toml::node* TableReader::find(std::string_view key, toml::node_type expected,
                                    Presence presence, std::string_view expectation) {
  const toml::node* node = find_any(key, presence, expectation);
  if (node != nullptr && node->type() != expected) {
    error(key, fmt::format("expected {}, got {}", type_name(expected), type_name(node->type())));
    return nullptr;
  }
  return node;
}

std::optional<std::int64_t> TableReader::integer(std::string_view key, std::int64_t min,
                                                 std::int64_t max, Presence presence) {
  const auto range = fmt::format("{}..{}", min, max);
  // A key whose range depends on another key (an address on its bus) is read unbounded.
  const bool bounded = min != std::numeric_limits<std::int64_t>::min() ||
                       max != std::numeric_limits<std::int64_t>::max();
  const toml::node* node = find(key, toml::node_type::integer, presence,
                                bounded ? fmt::format("an integer in {}", range) : "an integer");
  if (node == nullptr) return std::nullopt;
  const std::int64_t value = node->as_integer()->get();
  if (value < min || value > max) {
    error(key, fmt::format("{} is out of range, expected {}", value, range));
    return std::nullopt;
  }
  located_.mark_valid(key);
  return value;
}

std::optional<double> TableReader::number(std::string_view key, Presence presence,
                                          bool allow_nan) {
  const toml::node* node = find_any(key, presence, "a number");
  if (node == nullptr) return std::nullopt;
  double value = 0;
  if (const auto* i = node->as_integer()) {
    value = double(i->get());
  } else if (const auto* f = node->as_floating_point()) {
    value = f->get();
  } else {
    error(key, fmt::format("expected a number, got {}", type_name(node->type())));
    return std::nullopt;
  }
  if (!std::isfinite(value) && !(allow_nan && std::isnan(value))) {
    error(key, fmt::format("{} is not a finite number", value));
    return std::nullopt;
  }
  located_.mark_valid(key);
  return value;
}

std::optional<double> TableReader::number_in(std::string_view key, double min, double max,
                                             Presence presence) {
  const auto value = number(key, presence);
  if (!value) return std::nullopt;
  if (*value < min || *value > max) {
    error(key, fmt::format("{} is out of range, expected {}..{}", *value, min, max));
    return std::nullopt;
  }
  return value;
}

std::optional<bool> TableReader::boolean(std::string_view key, Presence presence) {
  const toml::node* node =
      find(key, toml::node_type::boolean, presence, "a boolean (true or false)");
  if (node == nullptr) return std::nullopt;
  located_.mark_valid(key);
  return node->as_boolean()->get();
}

std::optional<std::string> TableReader::string(std::string_view key, Presence presence) {
  const toml::node* node = find(key, toml::node_type::string, presence, "a string");
  if (node == nullptr) return std::nullopt;
  located_.mark_valid(key);
  return node->as_string()->get();
}

std::optional<std::string> TableReader::choice(std::string_view key,
                                               std::initializer_list<std::string_view> allowed,
                                               Presence presence) {
  return choice(key, std::span<const std::string_view>(allowed.begin(), allowed.size()), presence);
}

std::optional<std::string> TableReader::choice(std::string_view key,
                                               std::span<const std::string_view> allowed,
                                               Presence presence) {
  std::string expected;
  std::size_t index = 0;
  for (std::string_view option : allowed) {
    const bool last = ++index == allowed.size();
    expected += fmt::format("{}\"{}\"", index == 1 ? "" : last ? " or " : ", ", option);
  }
  const toml::node* node = find(key, toml::node_type::string, presence, expected);
  if (node == nullptr) return std::nullopt;
  const std::string& value = node->as_string()->get();
  if (std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
    const std::vector<std::string> options(allowed.begin(), allowed.end());
    const std::string guess = closest_name(value, options);
    error(key, guess.empty()
                   ? fmt::format("\"{}\" is not valid, expected {}", value, expected)
                   : fmt::format("\"{}\" is not valid; did you mean \"{}\"? (expected {})", value,
                                 guess, expected));
    return std::nullopt;
  }
  located_.mark_valid(key);
  return value;
}

std::optional<std::vector<std::string>> TableReader::strings(std::string_view key,
                                                             Presence presence) {
  const toml::node* node = find(key, toml::node_type::array, presence, "an array of strings");
  if (node == nullptr) return std::nullopt;
  std::vector<std::string> values;
  for (const toml::node& element : *node->as_array()) {
    if (!element.is_string()) {
      error(key, fmt::format("expected an array of strings, found {}", type_name(element.type())));
      return std::nullopt;
    }
    values.push_back(element.as_string()->get());
  }
  located_.mark_valid(key);
  return values;
}

std::optional<std::vector<std::int64_t>> TableReader::integers(std::string_view key,
                                                               std::int64_t min, std::int64_t max,
                                                               Presence presence) {
  const auto expected = fmt::format("an array of integers in {}..{}", min, max);
  const toml::node* node = find(key, toml::node_type::array, presence, expected);
  if (node == nullptr) return std::nullopt;
  std::vector<std::int64_t> values;
  for (const toml::node& element : *node->as_array()) {
    if (!element.is_integer()) {
      error(key, fmt::format("expected {}, found {}", expected, type_name(element.type())));
      return std::nullopt;
    }
    const std::int64_t value = element.as_integer()->get();
    if (value < min || value > max) {
      error(key, fmt::format("{} is out of range, expected {}", value, expected));
      return std::nullopt;
    }
    values.push_back(value);
  }
  located_.mark_valid(key);
  return values;
}

const toml::table* TableReader::table(std::string_view key, Presence presence) {
  const toml::node* node = find(key, toml::node_type::table, presence, "a table");
  if (node == nullptr) return nullptr;
  located_.mark_valid(key);
  return node->as_table();
}

const toml::node* TableReader::node(std::string_view key) {
  return find_any(key, Presence::optional, "");
}

namespace {

// "sensor[2].map.point[0]" -> "sensor.map.point"
std::string kind_of_table(std::string_view path) {
  std::string kind;
  bool in_index = false;
  for (char c : path) {
    if (c == '[') in_index = true;
    if (!in_index) kind += c;
    if (c == ']') in_index = false;
  }
  return kind;
}

}  // namespace

void TableReader::reject_unknown_keys() {
  if (AcceptedKeys* accepted = errors_.accepted_keys())
    (*accepted)[kind_of_table(located_.path())].insert(asked_.begin(), asked_.end());
  for (auto&& [key, node] : table_) {
    if (std::find(asked_.begin(), asked_.end(), key.str()) != asked_.end()) continue;
    const std::string guess = closest_key(key.str(), asked_);
    error(key.str(), guess.empty()
                         ? fmt::format("unknown key; expected one of: {}", join(asked_, ", "))
                         : fmt::format("unknown key; did you mean \"{}\"?", guess));
  }
}

void check_name(TableReader& in, std::string_view key, const std::string& name) {
  const bool safe = std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '.' || c == '-';
  });
  if (name.empty() || !safe)
    in.error(key, fmt::format("\"{}\" is not a valid name, expected one or more of the "
                              "letters A-Z a-z, digits 0-9, '_', '.' and '-'",
                              name));
}

}  // namespace tiltgate::toml_input
