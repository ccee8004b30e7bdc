#include "config/config_edit.h"

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

}  // namespace tiltgate
