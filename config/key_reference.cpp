#include "config/key_reference.h"

#include <algorithm>

#include "config/generated/configuration_md.h"

namespace tiltgate {

namespace {

std::string cell_trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}

// A table row's cells: split at each `|` that is not escaped (`\|`, as in "\|x\|"), the
// escape dropped.
std::vector<std::string> cells(std::string_view row) {
  std::vector<std::string> out;
  std::string cell;
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (row[i] == '\\' && i + 1 < row.size() && row[i + 1] == '|') {
      cell += '|';
      ++i;
    } else if (row[i] == '|') {
      out.push_back(cell_trimmed(cell));
      cell.clear();
    } else {
      cell += row[i];
    }
  }
  // "| a | b |": the text before the first bar and after the last is no cell.
  if (!out.empty()) out.erase(out.begin());
  return out;
}

std::string unquoted_code(std::string_view cell) {
  if (cell.size() >= 2 && cell.front() == '`' && cell.back() == '`')
    return std::string(cell.substr(1, cell.size() - 2));
  return std::string(cell);
}

// Each `"..."` of the allowed values, in order, once.
std::vector<std::string> quoted_values(std::string_view allowed) {
  std::vector<std::string> values;
  for (std::size_t at = allowed.find("`\""); at != std::string_view::npos;
       at = allowed.find("`\"", at + 1)) {
    const auto end = allowed.find("\"`", at + 2);
    if (end == std::string_view::npos) break;
    std::string value(allowed.substr(at + 2, end - at - 2));
    if (std::find(values.begin(), values.end(), value) == values.end()) values.push_back(value);
  }
  return values;
}

std::vector<KeyReference> joined(std::vector<KeyReference> first,
                                 const std::vector<KeyReference>& second) {
  first.insert(first.end(), second.begin(), second.end());
  return first;
}

}  // namespace

std::vector<KeyReference> reference_table(std::string_view markdown, std::string_view heading,
                                          std::string_view prefix) {
  std::vector<KeyReference> keys;
  const std::string line = "\n" + std::string(heading) + "\n";
  auto at = markdown.find(line);
  if (at == std::string_view::npos) return keys;
  at += line.size();
  bool in_table = false;
  int row_number = 0;
  while (at < markdown.size()) {
    auto end = markdown.find('\n', at);
    if (end == std::string_view::npos) end = markdown.size();
    const std::string_view text = markdown.substr(at, end - at);
    at = end + 1;
    if (text.starts_with("#")) break;  // the next section: this one has no table
    if (!text.starts_with("|")) {
      if (in_table) break;
      continue;
    }
    in_table = true;
    if (row_number++ < 2) continue;  // the header and its rule
    const std::vector<std::string> row = cells(text);
    if (row.size() < 6) continue;
    KeyReference key;
    key.key = std::string(prefix) + unquoted_code(row[0]);
    key.type = row[1];
    key.default_text = row[2];
    key.allowed = row[3];
    key.meaning = row[4];
    key.applies = row[5];
    key.required = key.default_text == "required";
    if (key.type == "string") key.choices = quoted_values(key.allowed);
    keys.push_back(std::move(key));
  }
  return keys;
}

const std::vector<KeyReference>& bus_keys() {
  static const std::vector<KeyReference> keys = reference_table(kConfigurationMd, "## `[[bus]]`");
  return keys;
}

const std::vector<KeyReference>& sensor_keys() {
  static const std::vector<KeyReference> keys =
      joined(joined(joined(joined(reference_table(kConfigurationMd, "## `[[sensor]]`"),
                                  reference_table(kConfigurationMd, "### `mounting`",
                                                  "mounting.")),
                           reference_table(kConfigurationMd, "### `baseline`", "baseline.")),
                    reference_table(kConfigurationMd, "### `alarms`", "alarms.")),
             reference_table(kConfigurationMd, "### `alarms.danger`", "alarms.danger."));
  return keys;
}

}  // namespace tiltgate
