// A scan's events as JSON (commission_wire/event_json_parts.h): its progress, each device found,
// and its end with the sensors found, the repeats dropped and the configuration tables.
#include "commission_wire/event_json_parts.h"

namespace tiltgate {

using json = nlohmann::json;

namespace {

json found_sensor_json(const FoundSensor& s) {
  return json{{"address", s.address},   {"baud", s.baud},   {"collision", s.collision},
              {"detail", s.detail},     {"model", s.model}, {"serial", s.serial},
              {"firmware", s.firmware}, {"lock_level", json_or_null(s.lock_level)}};
}

json found_sensors_json(const std::vector<FoundSensor>& found) {
  json list = json::array();
  for (const FoundSensor& s : found) list.push_back(found_sensor_json(s));
  return list;
}

FoundSensor read_found_sensor(const JsonObjectReader& r) {
  FoundSensor s;
  s.address = r.integer<std::uint32_t>("address");
  s.baud = r.integer<std::uint32_t>("baud");
  s.collision = r.boolean("collision");
  s.detail = r.string("detail");
  s.model = r.string("model");
  s.serial = r.string("serial");
  s.firmware = r.string("firmware");
  s.lock_level = r.optional_integer<std::uint16_t>("lock_level");
  return s;
}

json repeated_sensor_json(const RepeatedSensor& r) {
  return json{{"address", r.address},
              {"serial", r.serial},
              {"kept_baud", r.kept_baud},
              {"other_bauds", r.other_bauds}};
}

RepeatedSensor read_repeated_sensor(const JsonObjectReader& r) {
  return {r.integer<std::uint32_t>("address"), r.string("serial"),
          r.integer<std::uint32_t>("kept_baud"), r.integer_list<std::uint32_t>("other_bauds")};
}

json sensor_table_json(const SensorTable& t) {
  return json{{"address", t.address},         {"model", t.model},
              {"serial", t.serial},           {"firmware", t.firmware},
              {"text", t.text},               {"configured_as", t.configured_as},
              {"proposed_unit_id", t.proposed_unit_id}};
}

SensorTable read_sensor_table(const JsonObjectReader& r) {
  SensorTable t;
  t.address = r.integer<std::uint32_t>("address");
  t.model = r.string("model");
  t.serial = r.string("serial");
  t.firmware = r.string("firmware");
  t.text = r.string("text");
  // Both came after protocol 3 first went out: a gateway from before (running on until its
  // restart after an upgrade) sends neither, and its tables are taken as they are, unmarked.
  if (r.has("configured_as")) t.configured_as = r.string("configured_as");
  if (r.has("proposed_unit_id")) t.proposed_unit_id = r.integer<std::uint8_t>("proposed_unit_id");
  return t;
}

}  // namespace

json event_fields(const ProgressEvent& e) {
  return json{{"done", e.done},
              {"total", e.total},
              {"baud", e.baud},
              {"found", found_sensors_json(e.found)}};
}

void read_event_fields(const JsonObjectReader& r, ProgressEvent& e) {
  e.done = r.integer<std::size_t>("done");
  e.total = r.integer<std::size_t>("total");
  e.baud = r.integer<std::uint32_t>("baud");
  e.found = r.object_list<FoundSensor>("found", read_found_sensor);
}

json event_fields(const DeviceFoundEvent& e) {
  return json{{"sensor", found_sensor_json(e.sensor)}};
}

void read_event_fields(const JsonObjectReader& r, DeviceFoundEvent& e) {
  e.sensor = read_found_sensor(r.object("sensor"));
}

json event_fields(const ScanFinishedEvent& e) {
  json repeated = json::array();
  for (const RepeatedSensor& s : e.repeated) repeated.push_back(repeated_sensor_json(s));
  json tables = json::array();
  for (const SensorTable& t : e.tables) tables.push_back(sensor_table_json(t));
  return json{{"found", found_sensors_json(e.found)},
              {"repeated", std::move(repeated)},
              {"probes", e.probes},
              {"took_ms", e.took.count()},
              {"configuration", e.configuration},
              {"tables", std::move(tables)}};
}

void read_event_fields(const JsonObjectReader& r, ScanFinishedEvent& e) {
  e.found = r.object_list<FoundSensor>("found", read_found_sensor);
  e.repeated = r.object_list<RepeatedSensor>("repeated", read_repeated_sensor);
  e.probes = r.integer<std::size_t>("probes");
  e.took = std::chrono::milliseconds(r.integer<std::chrono::milliseconds::rep>("took_ms"));
  e.configuration = r.string("configuration");
  e.tables = r.object_list<SensorTable>("tables", read_sensor_table);
}

}  // namespace tiltgate
