#include "audit/audit_json.h"

#include <nlohmann/json.hpp>

namespace tiltgate {

namespace {

nlohmann::json to_json(const AuditRecord& record) {
  nlohmann::json object = {{"time_ms", record.unix_ms},  {"door", record.origin.door},
                           {"who", record.origin.who},   {"sensor", record.sensor},
                           {"setting", record.setting},  {"new", record.new_value},
                           {"result", record.result}};
  if (!record.old_value.empty()) object["old"] = record.old_value;
  return object;
}

}  // namespace

std::string audit_json(const std::vector<AuditRecord>& records) {
  nlohmann::json array = nlohmann::json::array();
  for (const AuditRecord& record : records) array.push_back(to_json(record));
  // Replaced, not thrown on: a sensor's reply may bring bytes that are not UTF-8 into a value.
  return array.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string audit_record_json(const AuditRecord& record) {
  return to_json(record).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string audit_record_json(const AuditRecord& record, std::string_view prev) {
  nlohmann::json object = to_json(record);
  object["prev"] = std::string(prev);
  return object.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::optional<std::string> audit_record_prev(std::string_view text) {
  const nlohmann::json object = nlohmann::json::parse(text, nullptr, false);
  if (!object.is_object()) return std::nullopt;
  const auto prev = object.find("prev");
  if (prev == object.end() || !prev->is_string()) return std::nullopt;
  return prev->get<std::string>();
}

std::optional<AuditRecord> audit_record_from_json(std::string_view text) {
  const nlohmann::json object = nlohmann::json::parse(text, nullptr, false);
  if (!object.is_object()) return std::nullopt;
  const auto text_of = [&](const char* key) {
    const auto it = object.find(key);
    return it != object.end() && it->is_string() ? it->get<std::string>() : std::string();
  };
  const auto time = object.find("time_ms");
  if (time == object.end() || !time->is_number_integer()) return std::nullopt;
  AuditRecord record;
  record.unix_ms = time->get<std::int64_t>();
  record.origin = {text_of("door"), text_of("who")};
  record.sensor = text_of("sensor");
  record.setting = text_of("setting");
  record.old_value = text_of("old");
  record.new_value = text_of("new");
  record.result = text_of("result");
  return record;
}

}  // namespace tiltgate
