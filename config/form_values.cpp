#include "config/form_values.h"

#include <algorithm>
#include <fmt/format.h>
#include <sstream>
#include <toml++/toml.h>

#include "toml/toml_parse.h"
#include "toml/toml_string.h"

namespace tiltgate {

namespace {

std::string trimmed(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return std::string(text.substr(first, last - first + 1));
}


template <typename Value>
std::string printed(const Value& value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// A value as a person types it; none for a value a form cannot show (a table, mixed types).
std::optional<std::string> typed_text(const toml::node& node) {
  if (const auto* text = node.as_string()) return text->get();
  if (const auto* integer = node.as_integer()) return std::to_string(integer->get());
  if (const auto* number = node.as_floating_point()) return printed(*number);
  if (const auto* boolean = node.as_boolean()) return boolean->get() ? "true" : "false";
  if (const auto* array = node.as_array()) {
    std::string list;
    for (const toml::node& element : *array) {
      const auto* integer = element.as_integer();
      if (integer == nullptr) return std::nullopt;
      list += (list.empty() ? "" : ", ") + std::to_string(integer->get());
    }
    return list;
  }
  return std::nullopt;
}

// `typed` read as a TOML value of one line, or none.
std::optional<toml::table> parsed_value(std::string_view typed) {
  if (typed.find_first_of("\r\n#") != std::string_view::npos) return std::nullopt;
  auto parsed = toml_input::parse_toml("v = " + std::string(typed), "");
  if (!parsed || !parsed->get("v")) return std::nullopt;
  return std::move(*parsed);
}

const toml::node* node_of(const toml::table& table, std::string_view key) {
  const auto dot = key.find('.');
  const toml::node* node = table.get(key.substr(0, dot));
  if (dot == std::string_view::npos || node == nullptr) return node;
  const toml::table* group = node->as_table();
  return group ? group->get(key.substr(dot + 1)) : nullptr;
}

}  // namespace

Expected<std::vector<FormTable>, std::string> form_tables(std::string_view text,
                                                          std::string_view array,
                                                          const std::vector<KeyReference>& keys) {
  auto root = toml_input::parse_toml(text, "");
  if (!root)
    return Unexpected{fmt::format("line {}: {}", root.error().where.line, root.error().description)};
  std::vector<FormTable> tables;
  const toml::array* list = (*root)[array].as_array();
  if (list == nullptr) return tables;
  for (const toml::node& element : *list) {
    const toml::table* table = element.as_table();
    if (table == nullptr) continue;
    FormTable form;
    form.line = int(table->source().begin.line);
    if (const auto name = table->get_as<std::string>("name")) form.name = name->get();
    for (const KeyReference& key : keys) {
      if (key.type == "table") continue;  // a group: its keys are listed after it
      const toml::node* node = node_of(*table, key.key);
      if (node == nullptr) continue;
      if (auto value = typed_text(*node))
        form.values[key.key] = std::move(*value);
      else
        form.fixed.push_back(key.key);
    }
    tables.push_back(std::move(form));
  }
  return tables;
}

std::set<std::uint8_t> unit_ids_in(std::string_view text) {
  std::set<std::uint8_t> ids;
  auto root = toml_input::parse_toml(text, "");
  if (!root) return ids;
  const auto take = [&](const toml::node* node) {
    if (const auto* id = node ? node->as_integer() : nullptr; id && id->get() >= 1 && id->get() <= 247)
      ids.insert(std::uint8_t(id->get()));
  };
  for (const char* array : {"sensor", "aggregate", "bus"}) {
    const toml::array* tables = (*root)[array].as_array();
    if (tables == nullptr) continue;
    for (const toml::node& element : *tables) {
      const toml::table* table = element.as_table();
      if (table == nullptr) continue;
      take(table->get("unit_id"));
      if (const toml::array* passed = table->get_as<toml::array>("pass_through"))
        for (const toml::node& id : *passed) take(&id);
    }
  }
  return ids;
}

Expected<std::string, std::string> toml_value(const KeyReference& key, std::string_view typed) {
  const std::string text = trimmed(typed);
  if (text.find_first_of("\r\n") != std::string::npos)
    return Unexpected{std::string("takes one line")};
  if (key.type.starts_with("string")) return toml_input::toml_string(text);
  const auto refused = [&](std::string_view what) {
    return Unexpected{fmt::format("\"{}\" is not {}", text, what)};
  };
  if (key.type == "integer") {
    const auto value = parsed_value(text);
    if (!value || !value->get("v")->is_integer()) return refused("a whole number");
    return std::to_string(value->get("v")->as_integer()->get());
  }
  if (key.type.starts_with("number")) {
    const auto value = parsed_value(text);
    if (!value) return refused("a number");
    const toml::node& number = *value->get("v");
    if (number.is_integer()) return std::to_string(number.as_integer()->get());
    if (number.is_floating_point()) return printed(*number.as_floating_point());
    return refused("a number");
  }
  if (key.type == "boolean") {
    if (text == "true" || text == "false") return text;
    return refused("true or false");
  }
  if (key.type == "array of integers") {
    const auto value = parsed_value("[" + text + "]");
    const toml::array* list = value ? value->get("v")->as_array() : nullptr;
    if (list == nullptr || !list->is_homogeneous(toml::node_type::integer))
      return refused("a list of whole numbers (1, 2, 3)");
    std::string out = "[";
    for (const toml::node& element : *list)
      out += (out.size() > 1 ? ", " : "") + std::to_string(element.as_integer()->get());
    return out + "]";
  }
  return Unexpected{std::string("cannot be set in a form; change it in the text")};
}

Expected<TableChanges, FieldErrors> table_changes(const std::map<std::string, std::string>& typed,
                                                  const FormTable* current,
                                                  const std::vector<KeyReference>& keys) {
  const auto current_text = [&](const std::string& key) -> std::string {
    if (current == nullptr) return {};
    const auto found = current->values.find(key);
    return found == current->values.end() ? std::string() : found->second;
  };
  const auto is_fixed = [&](std::string_view key) {
    return current != nullptr &&
           std::find(current->fixed.begin(), current->fixed.end(), key) != current->fixed.end();
  };
  const auto given = [&](const std::string& key) -> std::optional<std::string> {
    const auto found = typed.find(key);
    if (found == typed.end()) return std::nullopt;
    return trimmed(found->second);
  };
  const auto members_of = [&](const std::string& group) {
    std::vector<const KeyReference*> members;
    for (const KeyReference& key : keys)
      if (key.key.starts_with(group + ".")) members.push_back(&key);
    return members;
  };
  TableChanges changes;
  FieldErrors errors;
  for (const KeyReference& key : keys) {
    if (key.key.find('.') != std::string::npos) continue;  // in its group's place
    const std::vector<const KeyReference*> members = members_of(key.key);
    if (!members.empty()) {
      // A group is written whole, from what was typed and, for keys not sent, what it holds.
      bool changed = false;
      bool had = false;
      for (const KeyReference* member : members) {
        const auto value = given(member->key);
        changed = changed || (value && *value != current_text(member->key) && !is_fixed(member->key));
        had = had || !current_text(member->key).empty() || is_fixed(member->key);
      }
      if (!changed) continue;
      std::string written;
      for (const KeyReference* member : members) {
        const std::string value = given(member->key).value_or(current_text(member->key));
        if (value.empty()) continue;
        auto literal = toml_value(*member, value);
        if (!literal) {
          errors[member->key] = literal.error();
          continue;
        }
        written += fmt::format("{}{} = {}", written.empty() ? "" : ", ",
                               member->key.substr(key.key.size() + 1), *literal);
      }
      if (!written.empty())
        changes.emplace_back(key.key, "{ " + written + " }");
      else if (had)
        changes.emplace_back(key.key, std::nullopt);
      continue;
    }
    const auto value = given(key.key);
    if (!value || *value == current_text(key.key) || is_fixed(key.key)) continue;
    if (value->empty()) {
      changes.emplace_back(key.key, std::nullopt);
      continue;
    }
    auto literal = toml_value(key, *value);
    if (literal)
      changes.emplace_back(key.key, std::move(*literal));
    else
      errors[key.key] = literal.error();
  }
  if (!errors.empty()) return Unexpected{std::move(errors)};
  return changes;
}

TableValues values_of(const TableChanges& changes) {
  TableValues values;
  for (const auto& [key, value] : changes)
    if (value) values.emplace_back(key, *value);
  return values;
}

}  // namespace tiltgate
