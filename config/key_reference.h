// What the configuration reference (docs/configuration.md) says of each key of a [[bus]], a
// [[sensor]] and a sensor's `mounting` and `alarms`: its type, default, allowed values and
// meaning, read from the reference's own tables, which are compiled in. The console's forms
// (docs/web-console.md, "Guided configuration") show a key as the manual does, so they never
// fall behind it. Pure, apart from the compiled-in text.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace tiltgate {

struct KeyReference {
  std::string key;           // "baud"; a sensor's mounting and alarms keys: "mounting.invert_x"
  std::string type;          // "string", "integer", "number", "boolean", "array of integers", ...
  std::string default_text;  // as the reference writes it: "required", "`100`", "none"
  std::string allowed;       // markdown, as in the reference
  std::string meaning;       // markdown, as in the reference
  std::string applies;       // "at start", "per poll", ...
  bool required = false;     // the default is "required"
  // A string key's values when the reference lists them ("even", "odd", "none"); else empty.
  std::vector<std::string> choices;
};

// The rows of the first table after the line `heading` ("## `[[bus]]`") of a reference in the
// layout of docs/configuration.md (key | type | default | allowed | meaning | applies), each
// key prefixed with `prefix` ("mounting."). None when the heading or its table is missing.
std::vector<KeyReference> reference_table(std::string_view markdown, std::string_view heading,
                                          std::string_view prefix = {});

// docs/configuration.md as built into this binary: a [[bus]]'s keys; a [[sensor]]'s, then its
// mounting's and alarms' ("mounting.swap_axes").
const std::vector<KeyReference>& bus_keys();
const std::vector<KeyReference>& sensor_keys();

}  // namespace tiltgate
