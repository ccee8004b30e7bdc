// A [[bus]] or [[sensor]] as the console's forms show it (docs/web-console.md, "Guided
// configuration"): each key's value as a person types it (a string without its quotes, `true`,
// `1, 2, 3`; a sensor's mounting and alarms keys as "mounting.invert_x"), read from a
// configuration's text; and what a person typed turned back into a TOML value of the key's type
// (config/key_reference.h), or why not. Pure.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "config/config_edit.h"
#include "config/key_reference.h"
#include "driver/expected.h"

namespace tiltgate {

struct FormTable {
  std::string name;  // its `name` ("" when it has none, or not a string)
  int line = 0;      // its header's line
  std::map<std::string, std::string> values;  // key -> its value as typed
  // Keys written in a way a form cannot show (an inline map, a dotted key, a value of the wrong
  // type): the form leaves them as they are.
  std::vector<std::string> fixed;
};

// Every [[`array`]] of `text` ("bus", "sensor"), in order; why not when it is no valid TOML.
Expected<std::vector<FormTable>, std::string> form_tables(std::string_view text,
                                                          std::string_view array,
                                                          const std::vector<KeyReference>& keys);

// Every Modbus unit id `text` serves: its sensors', its aggregates', its buses' pass-through
// ids, as far as they are whole numbers (a text with errors too); none when it is no TOML.
std::set<std::uint8_t> unit_ids_in(std::string_view text);

// What was typed for `key` as a TOML value; why not ("\"fast\" is not a whole number").
Expected<std::string, std::string> toml_value(const KeyReference& key, std::string_view typed);

// A form's values for a table (key -> as typed; empty: not given) as the changes to make to
// `current` (none for a new table), in the reference's order: each key whose text changed, as
// its TOML value or none. The keys of a group ("mounting.") become one inline table
// (`mounting = { invert_x = true }`) in the group's place, written whole when any of them
// changed. Errors by key.
using FieldErrors = std::map<std::string, std::string>;
Expected<TableChanges, FieldErrors> table_changes(const std::map<std::string, std::string>& typed,
                                                  const FormTable* current,
                                                  const std::vector<KeyReference>& keys);

// The changes of a new table that give a value, for add_table().
TableValues values_of(const TableChanges& changes);

}  // namespace tiltgate
