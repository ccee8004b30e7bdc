// Changes one value of a configuration file in place, as `tiltgate set --config FILE --sensor
// NAME` does after it re-addressed a sensor or changed its baud: only the value's own text is
// replaced (or one line added), so the file keeps its comments, order and layout. Pure: text in,
// text out; the caller reads and writes the file.
#pragma once

#include <cstdint>
#include <string>
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

}  // namespace tiltgate
