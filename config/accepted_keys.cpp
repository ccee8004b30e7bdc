#include "config/accepted_keys.h"

#include <fmt/format.h>
#include <toml++/toml.h>

#include "config/sections.h"

namespace tiltgate::config {

using toml_input::AcceptedKeys;
using toml_input::ErrorList;
namespace {

// One table of each kind, and each protocol and model of every family, as some keys are asked
// for only there. Values are left out: a reader asks for every key it knows whether or not it
// is given.
std::string every_table(FamilyList families) {
  std::string text =
      "[server]\n[http]\n[mqtt]\n[sparkplug]\n[audit]\n[redundancy]\n[record]\n[[aggregate]]\n";
  for (const FamilyDescriptor* family : families)
    for (const ProtocolDescriptor& protocol : family->protocols)
      text += fmt::format("[[bus]]\nprotocol = \"{}\"\n", protocol.name);
  for (const FamilyDescriptor* family : families)
    for (const ModelDescriptor& model : family->models)
      text += fmt::format("[[sensor]]\nmodel = \"{}\"\nmounting = {{}}\n"
                          "alarms = {{ danger = {{}} }}\nbaseline = {{}}\n"
                          "map = {{ point = [{{}}] }}\n",
                          model.name);
  return text;
}

template <class Read>
void read_each(const toml::table& root, std::string_view name, Read read) {
  const toml::array* tables = root[name].as_array();
  if (tables == nullptr) return;
  for (std::size_t i = 0; i < tables->size(); ++i)
    if (const toml::table* table = tables->get(i)->as_table()) read(*table, i);
}

}  // namespace

AcceptedKeys accepted_keys(FamilyList families) {
  AcceptedKeys keys;
  ErrorList ignored{"accepted keys"};  // the probe lacks required values: errors are expected
  ignored.record_accepted_keys(&keys);
  const toml::table root = toml::parse(every_table(families));
  read_server(*root["server"].as_table(), ignored);
  read_http(*root["http"].as_table(), ignored);
  read_mqtt(*root["mqtt"].as_table(), ignored);
  read_sparkplug(*root["sparkplug"].as_table(), ignored);
  read_audit(*root["audit"].as_table(), ignored);
  read_redundancy(*root["redundancy"].as_table(), ignored);
  read_record(*root["record"].as_table(), ignored);
  read_each(root, "bus", [&](const toml::table& table, std::size_t i) {
    read_bus(table, "bus[" + std::to_string(i) + "]", ignored, families);
  });
  read_each(root, "sensor", [&](const toml::table& table, std::size_t i) {
    read_sensor(table, "sensor[" + std::to_string(i) + "]", ignored, families);
  });
  read_each(root, "aggregate", [&](const toml::table& table, std::size_t i) {
    read_aggregate(table, "aggregate[" + std::to_string(i) + "]", ignored);
  });
  return keys;
}

}  // namespace tiltgate::config
