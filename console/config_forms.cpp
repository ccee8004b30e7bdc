#include "console/config_forms.h"

#include <fmt/format.h>
#include <set>
#include <utility>

#include "commission/configured_units.h"
#include "config/config_edit.h"
#include "config/config_loader.h"
#include "config/form_values.h"
#include "config/machine_checks.h"
#include "console/console_reply.h"

namespace tiltgate {

namespace {

using json = nlohmann::json;

const std::vector<KeyReference>& keys_of(std::string_view table) {
  return table == "bus" ? bus_keys() : sensor_keys();
}

json keys_json(const std::vector<KeyReference>& keys) {
  json list = json::array();
  for (const KeyReference& key : keys)
    list.push_back({{"key", key.key},
                    {"type", key.type},
                    {"default", key.default_text},
                    {"allowed", key.allowed},
                    {"meaning", key.meaning},
                    {"applies", key.applies},
                    {"required", key.required},
                    {"choices", key.choices}});
  return list;
}

json tables_json(const std::vector<FormTable>& tables) {
  json list = json::array();
  for (const FormTable& table : tables)
    list.push_back({{"name", table.name},
                    {"line", table.line},
                    {"values", table.values},
                    {"fixed", table.fixed}});
  return list;
}

// A form's answer that changes nothing: what is wrong, each at its field when it has one.
HttpReply refused(const std::map<std::string, std::string>& by_field, std::string general = {}) {
  json errors = json::array();
  for (const auto& [field, message] : by_field)
    errors.push_back({{"field", field}, {"line", 0}, {"key", field}, {"message", message},
                      {"text", fmt::format("{}: {}", field, message)}, {"before", false}});
  if (!general.empty())
    errors.push_back({{"field", nullptr}, {"line", 0}, {"key", ""}, {"message", general},
                      {"text", general}, {"before", false}});
  return json_reply(200, json{{"ok", false}, {"text", nullptr}, {"line", 0}, {"errors", errors}});
}

// The index of the table whose header is at `line` among `array`'s of `text`; none.
std::optional<std::size_t> index_at(std::string_view text, std::string_view array,
                                    int line) {
  const auto tables = form_tables(text, array, keys_of(array));
  if (!tables) return std::nullopt;
  for (std::size_t i = 0; i < tables->size(); ++i)
    if ((*tables)[i].line == line) return i;
  return std::nullopt;
}

}  // namespace

HttpReply ConfigForms::keys() const {
  return json_reply(200, json{{"bus", keys_json(bus_keys())}, {"sensor", keys_json(sensor_keys())}});
}

HttpReply ConfigForms::tables(const ConfigText& text) const {
  const auto buses = form_tables(text.text, "bus", bus_keys());
  const auto sensors = form_tables(text.text, "sensor", sensor_keys());
  if (!buses || !sensors)
    return json_reply(200, json{{"buses", json::array()}, {"sensors", json::array()},
                                {"free_unit_id", nullptr},
                                {"error", "not valid TOML: " + (buses ? sensors.error() : buses.error())}});
  const std::vector<std::uint8_t> free = free_unit_ids(unit_ids_in(text.text), 1);
  return json_reply(200, json{{"buses", tables_json(*buses)},
                              {"sensors", tables_json(*sensors)},
                              {"free_unit_id", free.empty() ? json(nullptr) : json(free.front())},
                              {"error", nullptr}});
}

HttpReply ConfigForms::edit(const FormEditRequest& request) const {
  const std::vector<KeyReference>& keys = keys_of(request.table);
  const auto current = form_tables(request.text, request.table, keys);
  if (!current) return refused({}, "the text is not valid TOML (" + current.error() + "): correct it in the editor first");
  Expected<TableEdit, std::string> edit = Unexpected{std::string()};
  if (request.action == "remove") {
    edit = remove_table(request.text, request.table, request.name);
  } else {
    const FormTable* before = nullptr;
    if (request.action == "edit") {
      for (const FormTable& table : *current)
        if (table.name == request.name) before = &table;
      if (before == nullptr)
        return refused({}, fmt::format("no [[{}]] named \"{}\"", request.table, request.name));
    }
    const auto changes = table_changes(request.values, before, keys);
    if (!changes) return refused(changes.error());
    edit = before ? change_table(request.text, request.table, request.name, *changes)
                  : add_table(request.text, request.table, values_of(*changes));
  }
  if (!edit) return refused({}, edit.error());
  // Checked as the served file, and as `tiltgate check` checks it. What was wrong before the
  // form (a tty unplugged on this machine, a typo elsewhere) is said, but only what the form
  // brought in stops it.
  const std::string name = path_.empty() ? std::string("(console)") : path_;
  const auto check = [&](std::string_view text) {
    return checked_on_this_machine(load_config_string(text, name, families_));
  };
  const auto loaded = check(edit->text);
  json errors = json::array();
  bool ok = true;
  if (!loaded) {
    std::set<std::pair<std::string, std::string>> before;
    if (const auto earlier = check(request.text); !earlier)
      for (const FileError& error : earlier.error()) before.emplace(error.key, error.message);
    const auto index = edit->line > 0 ? index_at(edit->text, request.table, edit->line)
                                      : std::nullopt;
    const std::string own = index ? fmt::format("{}[{}].", request.table, *index) : std::string();
    for (const FileError& error : loaded.error()) {
      const bool mine = !own.empty() && error.key.starts_with(own);
      const bool earlier = before.count({error.key, error.message}) > 0;
      ok = ok && earlier;
      errors.push_back({{"field", mine ? json(error.key.substr(own.size())) : json(nullptr)},
                        {"line", error.line},
                        {"key", error.key},
                        {"message", error.message},
                        {"text", error.to_string()},
                        {"before", earlier}});
    }
  }
  return json_reply(200, json{{"ok", ok},
                              {"text", edit->text},
                              {"line", edit->line},
                              {"errors", errors}});
}

}  // namespace tiltgate
