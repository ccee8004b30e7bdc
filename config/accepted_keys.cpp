#include "config/accepted_keys.h"

#include <toml++/toml.h>

#include "config/sections.h"

namespace tiltgate::config {
namespace {

// One table of each kind, and each protocol and model, as some keys are asked for only there.
// Values are left out: a reader asks for every key it knows whether or not it is given.
constexpr std::string_view kEveryTable = R"(
[server]

[[bus]]
protocol = "rieker"
[[bus]]
protocol = "spectron-9bit"
[[bus]]
protocol = "spectron-modbus"

[[sensor]]
model = "h6"
mounting = {}
alarms = {}
map = { point = [{}] }
[[sensor]]
model = "h4360"
mounting = {}
alarms = {}
map = { point = [{}] }
[[sensor]]
model = "dyna"
mounting = {}
alarms = {}
map = { point = [{}] }
)";

template <class Read>
void read_each(const toml::table& root, std::string_view name, Read read) {
  const toml::array* tables = root[name].as_array();
  if (tables == nullptr) return;
  for (std::size_t i = 0; i < tables->size(); ++i)
    if (const toml::table* table = tables->get(i)->as_table()) read(*table, i);
}

}  // namespace

AcceptedKeys accepted_keys() {
  AcceptedKeys keys;
  ErrorList ignored{"accepted keys"};  // the probe lacks required values: errors are expected
  ignored.record_accepted_keys(&keys);
  const toml::table root = toml::parse(kEveryTable);
  read_server(*root["server"].as_table(), ignored);
  read_each(root, "bus", [&](const toml::table& table, std::size_t i) {
    read_bus(table, "bus[" + std::to_string(i) + "]", ignored);
  });
  read_each(root, "sensor", [&](const toml::table& table, std::size_t i) {
    read_sensor(table, "sensor[" + std::to_string(i) + "]", ignored);
  });
  return keys;
}

}  // namespace tiltgate::config
