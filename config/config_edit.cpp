#include "config/config_edit.h"

#include <algorithm>
#include <fmt/format.h>
#include <toml++/toml.h>

#include "toml/toml_parse.h"

namespace tiltgate {

namespace {

// The byte offset of a toml++ source position (1-based line, and column counted in code points).
std::optional<std::size_t> offset_of(std::string_view text, toml::source_position position) {
  std::size_t offset = 0;
  for (toml::source_index line = 1; line < position.line; ++line) {
    offset = text.find('\n', offset);
    if (offset == std::string_view::npos) return std::nullopt;
    ++offset;
  }
  for (toml::source_index column = 1; column < position.column; ++column) {
    if (offset >= text.size() || text[offset] == '\n') return std::nullopt;
    ++offset;
    // Skip a code point's continuation bytes.
    while (offset < text.size() && (static_cast<unsigned char>(text[offset]) & 0xC0) == 0x80)
      ++offset;
  }
  return offset;
}

// The length of an integer's text from `offset` (decimal, 0x / 0o / 0b, digit separators, sign).
std::size_t integer_length(std::string_view text, std::size_t offset) {
  std::size_t end = offset;
  while (end < text.size()) {
    const char c = text[end];
    const bool part = (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F') ||
                      c == 'x' || c == 'o' || c == '_' || c == '+' || c == '-';
    if (!part) break;
    ++end;
  }
  return end - offset;
}

Expected<toml::table, std::string> parse(std::string_view text) {
  auto parsed = toml_input::parse_toml(text, "");
  if (!parsed) return Unexpected{fmt::format("not valid TOML: {}", parsed.error().description)};
  return std::move(*parsed);
}

// The table of `array` (a [[sensor]] or [[bus]] list) whose `name` is `name`.
const toml::table* named_table(const toml::table& root, std::string_view array,
                               std::string_view name) {
  const toml::array* tables = root[array].as_array();
  if (!tables) return nullptr;
  for (const toml::node& node : *tables) {
    const toml::table* table = node.as_table();
    if (table && table->get_as<std::string>("name") &&
        table->get_as<std::string>("name")->get() == name)
      return table;
  }
  return nullptr;
}

Expected<ConfigEdit, std::string> replace_integer(std::string_view text, const toml::node& value,
                                                  std::int64_t new_value) {
  if (!value.is_integer()) return Unexpected{std::string("is not a whole number")};
  const toml::source_position begin = value.source().begin;
  const std::optional<std::size_t> offset = offset_of(text, begin);
  if (!offset) return Unexpected{std::string("its place in the file was not found")};
  const std::size_t length = integer_length(text, *offset);
  if (length == 0) return Unexpected{std::string("its place in the file was not found")};
  ConfigEdit edit;
  edit.old_value = std::string(text.substr(*offset, length));
  edit.text = std::string(text.substr(0, *offset)) + std::to_string(new_value) +
              std::string(text.substr(*offset + length));
  edit.line = int(begin.line);
  return edit;
}


// Where 1-based line `line` starts; the text's end past its last line.
std::size_t line_start(std::string_view text, int line) {
  std::size_t offset = 0;
  for (int at = 1; at < line; ++at) {
    offset = text.find('\n', offset);
    if (offset == std::string_view::npos) return text.size();
    ++offset;
  }
  return offset;
}

std::string_view line_text(std::string_view text, int line) {
  const std::size_t start = line_start(text, line);
  const std::size_t end = std::min(text.find('\n', start), text.size());
  return text.substr(start, end - start);
}

std::string_view without_indent(std::string_view line) {
  const std::size_t first = line.find_first_not_of(" \t");
  return first == std::string_view::npos ? std::string_view{} : line.substr(first);
}

int line_count(std::string_view text) {
  int lines = int(std::count(text.begin(), text.end(), '\n'));
  if (!text.empty() && text.back() != '\n') ++lines;
  return lines;
}

// A table written under a header of its own ([[sensor]], [sensor.mounting]), not inline and
// not made by dotted keys.
bool has_header(std::string_view text, const toml::table& table) {
  return !table.is_inline() &&
         without_indent(line_text(text, int(table.source().begin.line))).starts_with("[");
}

// The header lines of every table of `node` with one, but not of `skip` or its own tables.
void header_lines(std::string_view text, const toml::node& node, const toml::table* skip,
                  std::vector<int>& lines) {
  if (const toml::table* table = node.as_table()) {
    if (table == skip) return;
    if (has_header(text, *table)) lines.push_back(int(table->source().begin.line));
    for (const auto& entry : *table) header_lines(text, entry.second, skip, lines);
  } else if (const toml::array* array = node.as_array()) {
    for (const toml::node& element : *array) header_lines(text, element, skip, lines);
  }
}

// The last line of a table with a header: the line before the next header that is not one of
// its own tables, less the blank lines and comments before that header (they belong to it).
int last_line_of(std::string_view text, const toml::table& root, const toml::table& table) {
  const int header = int(table.source().begin.line);
  std::vector<int> others;
  header_lines(text, root, &table, others);
  int last = line_count(text);
  for (const int line : others)
    if (line > header) last = std::min(last, line - 1);
  while (last > header) {
    const std::string_view line = without_indent(line_text(text, last));
    if (!line.empty() && !line.starts_with("#")) break;
    --last;
  }
  return last;
}

// A change of the text: [begin, end) replaced by `with`.
struct Splice {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::string with;
};

// Splices that do not overlap, made from the last to the first: an insertion where a removal
// begins goes after the removal.
std::string spliced(std::string_view text, std::vector<Splice> splices) {
  std::sort(splices.begin(), splices.end(), [](const Splice& a, const Splice& b) {
    return a.begin != b.begin ? a.begin > b.begin : a.end > b.end;
  });
  std::string out(text);
  for (const Splice& splice : splices)
    out.replace(splice.begin, splice.end - splice.begin, splice.with);
  return out;
}

Splice removed_lines(std::string_view text, int first, int last) {
  return Splice{line_start(text, first), line_start(text, last + 1), {}};
}

// The [[`array`]] table named `name`, one with a header of its own, or why not.
Expected<const toml::table*, std::string> header_table(std::string_view text,
                                                       const toml::table& root,
                                                       std::string_view array,
                                                       std::string_view name) {
  const toml::table* table = named_table(root, array, name);
  if (!table) return Unexpected{fmt::format("no [[{}]] named \"{}\"", array, name)};
  if (!has_header(text, *table))
    return Unexpected{fmt::format("[[{}]] \"{}\" is not written under a [[{}]] header of its "
                                  "own; change it in the text", array, name, array)};
  return table;
}

}  // namespace

Expected<ConfigEdit, std::string> edit_sensor_address(std::string_view text,
                                                      std::string_view sensor,
                                                      std::int64_t address) {
  const auto root = parse(text);
  if (!root) return Unexpected{root.error()};
  const toml::table* table = named_table(*root, "sensor", sensor);
  if (!table) return Unexpected{fmt::format("no [[sensor]] named \"{}\"", sensor)};
  const toml::node* value = table->get("address");
  if (!value) return Unexpected{fmt::format("[[sensor]] \"{}\" has no address", sensor)};
  auto edit = replace_integer(text, *value, address);
  if (!edit) return Unexpected{fmt::format("[[sensor]] \"{}\" address {}", sensor, edit.error())};
  return edit;
}

Expected<ConfigEdit, std::string> edit_bus_baud(std::string_view text, std::string_view bus,
                                                std::int64_t baud) {
  const auto root = parse(text);
  if (!root) return Unexpected{root.error()};
  const toml::table* table = named_table(*root, "bus", bus);
  if (!table) return Unexpected{fmt::format("no [[bus]] named \"{}\"", bus)};
  if (const toml::node* value = table->get("baud")) {
    auto edit = replace_integer(text, *value, baud);
    if (!edit) return Unexpected{fmt::format("[[bus]] \"{}\" baud {}", bus, edit.error())};
    return edit;
  }
  // No baud yet: a line of its own after the bus's name, indented as that line is. A bus
  // written as an inline table has no line of its own to follow.
  if (table->is_inline())
    return Unexpected{fmt::format("[[bus]] \"{}\" is an inline table; add baud = {} to it by hand",
                                  bus, baud)};
  const toml::source_position name_at = table->get("name")->source().begin;
  const std::optional<std::size_t> name_offset = offset_of(text, name_at);
  if (!name_offset) return Unexpected{fmt::format("[[bus]] \"{}\": its name's place was not found", bus)};
  const std::size_t line_start = text.rfind('\n', *name_offset) == std::string_view::npos
                                     ? 0
                                     : text.rfind('\n', *name_offset) + 1;
  std::size_t indent_end = line_start;
  while (indent_end < text.size() && (text[indent_end] == ' ' || text[indent_end] == '\t'))
    ++indent_end;
  const std::string_view indent = text.substr(line_start, indent_end - line_start);
  // The key goes right after `name = ...` when that is all the line holds; else after the line.
  std::size_t line_end = text.find('\n', *name_offset);
  const bool at_end_of_file = line_end == std::string_view::npos;
  if (at_end_of_file) line_end = text.size();
  ConfigEdit edit;
  edit.text = std::string(text.substr(0, line_end)) + "\n" + std::string(indent) +
              fmt::format("baud = {}", baud) + (at_end_of_file ? "\n" : "") +
              std::string(text.substr(line_end));
  edit.line = int(name_at.line) + 1;
  return edit;
}

Expected<TableEdit, std::string> add_table(std::string_view text, std::string_view array,
                                           const TableValues& values) {
  if (const auto root = parse(text); !root) return Unexpected{root.error()};
  std::string out(text);
  if (!out.empty() && out.back() != '\n') out += '\n';
  if (!out.empty() && !out.ends_with("\n\n")) out += '\n';
  TableEdit edit;
  edit.line = line_count(out) + 1;
  out += fmt::format("[[{}]]\n", array);
  for (const auto& [key, value] : values) out += fmt::format("{} = {}\n", key, value);
  edit.text = std::move(out);
  return edit;
}

Expected<TableEdit, std::string> change_table(std::string_view text, std::string_view array,
                                              std::string_view name, const TableChanges& changes) {
  const auto root = parse(text);
  if (!root) return Unexpected{root.error()};
  const auto found = header_table(text, *root, array, name);
  if (!found) return Unexpected{found.error()};
  const toml::table& table = **found;
  const int header = int(table.source().begin.line);
  // Added keys go after the table's last value, before any table of its own.
  int last_value = header;
  for (const auto& [key, node] : table) {
    const toml::table* own = node.as_table();
    const toml::array* list = node.as_array();
    const bool tables = (own && !own->is_inline()) ||
                        (list && !list->empty() && list->is_array_of_tables() &&
                         !list->front().as_table()->is_inline());
    if (!tables) last_value = std::max(last_value, int(node.source().end.line));
  }
  std::vector<Splice> splices;
  std::string added;
  for (const auto& change : changes) {
    // Named, not structured bindings: the lambda below captures the key, which clang refuses
    // of a binding.
    const std::string& key = change.first;
    const std::optional<std::string>& value = change.second;
    const toml::node* node = table.get(key);
    const auto cannot = [&](std::string_view why) {
      return Unexpected{fmt::format("[[{}]] \"{}\" {} {}; change it in the text", array, name, key, why)};
    };
    if (node == nullptr) {
      if (value) added += fmt::format("{} = {}\n", key, *value);
      continue;
    }
    if (const toml::table* own = node->as_table(); own && !own->is_inline()) {
      if (!has_header(text, *own)) return cannot("is written as dotted keys");
      splices.push_back(removed_lines(text, int(own->source().begin.line),
                                      last_line_of(text, *root, *own)));
      if (value) added += fmt::format("{} = {}\n", key, *value);
      continue;
    }
    if (const toml::array* list = node->as_array(); list && list->is_array_of_tables() &&
                                                    !list->empty() &&
                                                    !list->front().as_table()->is_inline())
      return cannot("is written as tables of its own");
    const auto begin = offset_of(text, node->source().begin);
    const auto end = offset_of(text, node->source().end);
    if (!begin || !end) return cannot("was not found in the text");
    if (value) {
      splices.push_back(Splice{*begin, *end, *value});
      continue;
    }
    // A removed key takes its line with it, when the line is its own.
    const int first = int(node->source().begin.line);
    const std::string_view line = without_indent(line_text(text, first));
    if (!line.starts_with(key) || line.substr(key.size()).find_first_not_of(" \t") !=
                                      line.substr(key.size()).find('='))
      return cannot("shares its line with another key");
    splices.push_back(removed_lines(text, first, int(node->source().end.line)));
  }
  if (!added.empty()) {
    std::size_t at = line_start(text, last_value + 1);
    if (at == text.size() && !text.empty() && text.back() != '\n') added.insert(0, "\n");
    splices.push_back(Splice{at, at, added});
  }
  return TableEdit{spliced(text, std::move(splices)), header};
}

Expected<TableEdit, std::string> remove_table(std::string_view text, std::string_view array,
                                              std::string_view name) {
  const auto root = parse(text);
  if (!root) return Unexpected{root.error()};
  const auto found = header_table(text, *root, array, name);
  if (!found) return Unexpected{found.error()};
  int first = int((*found)->source().begin.line);
  const int last = last_line_of(text, *root, **found);
  // One blank line between what was before it and what comes after, not two.
  if (first > 1 && without_indent(line_text(text, first - 1)).empty() &&
      (last + 1 > line_count(text) || without_indent(line_text(text, last + 1)).empty()))
    --first;
  return TableEdit{spliced(text, {removed_lines(text, first, last)}), 0};
}

}  // namespace tiltgate
