// Changes a configuration file's text in place, so the file keeps its comments, order and
// layout: one value, as `tiltgate set --config FILE --sensor NAME` does after it re-addressed a
// sensor or changed its baud (only the value's own text is replaced, or one line added); and a
// whole [[bus]] or [[sensor]] added, changed key by key or removed, as the console's forms do
// (docs/web-console.md, "Guided configuration"). Pure: text in, text out; the caller reads and
// writes the file.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>
#include <string_view>

#include "driver/expected.h"

namespace tiltgate {

struct ConfigEdit {
  std::string text;       // the whole file, changed
  int line = 0;           // 1-based line of the changed or added value
  std::string old_value;  // the value's text before; empty when the key was added
};

// `address` of the [[sensor]] named `sensor`.
Expected<ConfigEdit, std::string> edit_sensor_address(std::string_view text,
                                                      std::string_view sensor,
                                                      std::int64_t address);

// `baud` of the [[bus]] named `bus`, added on the line after its `name` when the bus has none.
Expected<ConfigEdit, std::string> edit_bus_baud(std::string_view text, std::string_view bus,
                                                std::int64_t baud);

// A table's keys and their TOML values as written ("\"line1\"", "125000", "{ invert_x = true }").
using TableValues = std::vector<std::pair<std::string, std::string>>;
// Keys to change, in the order added ones are written: each to a new TOML value, or to none
// (the key is removed: its default holds).
using TableChanges = std::vector<std::pair<std::string, std::optional<std::string>>>;

struct TableEdit {
  std::string text;  // the whole file, changed
  int line = 0;      // 1-based line of the table's header; 0 when it was removed
};

// A new [[`array`]] ("bus", "sensor") with `values` in their order, after the file's last line.
Expected<TableEdit, std::string> add_table(std::string_view text, std::string_view array,
                                           const TableValues& values);

// The [[`array`]] named `name` with `changes` made: a value's own text replaced, a removed key's
// line dropped, an added key on a line after the table's last value. A key written as a table of
// its own ([sensor.mounting]) is replaced by its new value on one line. Every other line stays.
Expected<TableEdit, std::string> change_table(std::string_view text, std::string_view array,
                                              std::string_view name, const TableChanges& changes);

// The file without the [[`array`]] named `name`: its header and keys, and its own tables
// ([sensor.mounting], [[sensor.map.point]]); comments after it, before the next table, stay.
Expected<TableEdit, std::string> remove_table(std::string_view text, std::string_view array,
                                              std::string_view name);

}  // namespace tiltgate
