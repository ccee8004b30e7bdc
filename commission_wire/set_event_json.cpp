// What `set` reports as JSON (commission_wire/event_json_parts.h): each write's answer, the setting
// applied, a move to another address, a restart, the configuration file that followed and the
// values read back.
#include "commission_wire/event_json_parts.h"

namespace tiltgate {

using json = nlohmann::json;

namespace {

json setting_value_json(const SettingValue& s) {
  return json{{"name", s.name}, {"value", json_or_null(s.value)}};
}

SettingValue read_setting_value(const JsonObjectReader& r) {
  return {r.string("name"), r.optional_number("value")};
}

}  // namespace

json event_fields(const SettingAcknowledgedEvent& e) {
  return json{{"address", e.address},
              {"setting", e.setting},
              {"old_value", json_or_null(e.old_value)},
              {"value", e.value},
              {"result", e.result},
              {"refusal_code", json_or_null(e.refusal_code)},
              {"detail", e.detail}};
}

void read_event_fields(const JsonObjectReader& r, SettingAcknowledgedEvent& e) {
  e.address = r.integer<std::uint32_t>("address");
  e.setting = r.string("setting");
  e.old_value = r.optional_number("old_value");
  e.value = r.number("value");
  e.result = r.string("result");
  e.refusal_code = r.optional_integer<std::uint8_t>("refusal_code");
  e.detail = r.string("detail");
}

json event_fields(const SettingAppliedEvent& e) {
  return json{{"setting", e.setting}, {"permanent", e.permanent}, {"address", e.address}};
}

void read_event_fields(const JsonObjectReader& r, SettingAppliedEvent& e) {
  e.setting = r.string("setting");
  e.permanent = r.boolean("permanent");
  e.address = r.integer<std::uint32_t>("address");
}

json event_fields(const AddressMovedEvent& e) {
  return json{{"from", e.from}, {"to", e.to}, {"gateway_sensor", e.gateway_sensor}};
}

void read_event_fields(const JsonObjectReader& r, AddressMovedEvent& e) {
  e.from = r.integer<std::uint32_t>("from");
  e.to = r.integer<std::uint32_t>("to");
  e.gateway_sensor = r.string("gateway_sensor");
}

json event_fields(const SensorRestartedEvent& e) {
  return json{
      {"baud", json_or_null(e.baud)}, {"line_follows", e.line_follows}, {"bus_baud", e.bus_baud}};
}

void read_event_fields(const JsonObjectReader& r, SensorRestartedEvent& e) {
  e.baud = r.optional_integer<std::uint32_t>("baud");
  e.line_follows = r.boolean("line_follows");
  e.bus_baud = r.integer<std::uint32_t>("bus_baud");
}

json event_fields(const ConfigUpdatedEvent& e) {
  return json{{"file", e.file}, {"changes", e.changes}};
}

void read_event_fields(const JsonObjectReader& r, ConfigUpdatedEvent& e) {
  e.file = r.string("file");
  e.changes = r.string_list("changes");
}

json event_fields(const SettingsReadEvent& e) {
  json settings = json::array();
  for (const SettingValue& s : e.settings) settings.push_back(setting_value_json(s));
  return json{{"address", e.address}, {"settings", std::move(settings)}};
}

void read_event_fields(const JsonObjectReader& r, SettingsReadEvent& e) {
  e.address = r.integer<std::uint32_t>("address");
  e.settings = r.object_list<SettingValue>("settings", read_setting_value);
}

}  // namespace tiltgate
