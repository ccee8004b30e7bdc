// The console's forms describe each key as docs/configuration.md does: the reference's tables,
// compiled in, read row by row.
#include <doctest/doctest.h>

#include <algorithm>

#include "config/accepted_keys.h"
#include "config/key_reference.h"

using namespace tiltgate;

namespace {

const KeyReference* find(const std::vector<KeyReference>& keys, std::string_view name) {
  const auto found = std::find_if(keys.begin(), keys.end(),
                                  [&](const KeyReference& key) { return key.key == name; });
  return found == keys.end() ? nullptr : &*found;
}

}  // namespace

TEST_CASE("key reference: a table's rows, escaped bars kept, quoted values as choices") {
  const std::string_view markdown =
      "# Title\n\n## `[[bus]]`\n\nSome words.\n\n"
      "| key | type | default | allowed | meaning | applies |\n"
      "| --- | --- | --- | --- | --- | --- |\n"
      "| `name` | string | required | letters | what sensors name | at start |\n"
      "| `parity` | string | `\"even\"` | `\"even\"`, `\"odd\"`, `\"none\"` | framing | at start |\n"
      "| `tilt` | number | none | 0..180 | \\|x\\| on one axis | per poll |\n"
      "\nAfter the table.\n\n## `[[sensor]]`\n";
  const std::vector<KeyReference> keys = reference_table(markdown, "## `[[bus]]`", "p.");
  REQUIRE(keys.size() == 3);
  CHECK(keys[0].key == "p.name");
  CHECK(keys[0].required);
  CHECK(keys[0].choices.empty());
  CHECK(keys[1].choices == std::vector<std::string>{"even", "odd", "none"});
  CHECK(keys[1].default_text == "`\"even\"`");
  CHECK_FALSE(keys[1].required);
  CHECK(keys[2].meaning == "|x| on one axis");
  CHECK(keys[2].type == "number");
  CHECK(reference_table(markdown, "## `[[sensor]]`").empty());  // a heading with no table
  CHECK(reference_table(markdown, "## nowhere").empty());
}

TEST_CASE("key reference: the built-in reference has every bus and sensor key the loader reads") {
  const toml_input::AcceptedKeys accepted = config::accepted_keys(registered_families());
  for (const auto& [kind, keys, prefix] :
       {std::tuple{std::string("bus"), &bus_keys(), std::string()},
        std::tuple{std::string("sensor"), &sensor_keys(), std::string()},
        std::tuple{std::string("sensor.mounting"), &sensor_keys(), std::string("mounting.")},
        std::tuple{std::string("sensor.baseline"), &sensor_keys(), std::string("baseline.")},
        std::tuple{std::string("sensor.alarms"), &sensor_keys(), std::string("alarms.")},
        std::tuple{std::string("sensor.alarms.danger"), &sensor_keys(),
                   std::string("alarms.danger.")}}) {
    const std::string table = kind;  // not a structured binding: CHECK_MESSAGE captures it
    for (const std::string& key : accepted.at(table))
      CHECK_MESSAGE(find(*keys, prefix + key) != nullptr, table << "." << key);
  }
  const KeyReference* protocol = find(bus_keys(), "protocol");
  REQUIRE(protocol != nullptr);
  CHECK(protocol->choices == std::vector<std::string>{"rieker", "spectron-9bit", "spectron-modbus",
                                                      "modbus-rtu", "modbus-tcp"});
  const KeyReference* invert = find(sensor_keys(), "mounting.invert_x");
  REQUIRE(invert != nullptr);
  CHECK(invert->type == "boolean");
  CHECK(find(sensor_keys(), "unit_id")->required);
}
