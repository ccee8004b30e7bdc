#include "console/audit_endpoint.h"

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>

#include "console/console_reply.h"
#include "status/history_format.h"

namespace tiltgate {

using json = nlohmann::json;

HttpReply audit_reply(const AuditTrail* trail, std::string_view target) {
  if (trail == nullptr) return json_reply(200, json{{"records", json::array()}});
  AuditTrail::Filter filter;
  filter.door = query_value(target, "door");
  filter.sensor = query_value(target, "sensor");
  filter.who = query_value(target, "who");
  filter.setting = query_value(target, "setting");
  const std::string limit = query_value(target, "limit");
  if (!limit.empty()) {
    char* stop = nullptr;
    const long n = std::strtol(limit.c_str(), &stop, 10);
    if (stop == limit.c_str() || *stop != '\0' || n < 1 || n > 10000)
      return error_reply(400, "limit: expected 1 to 10000");
    filter.limit = std::size_t(n);
  }
  json records = json::array();
  for (const AuditRecord& record : trail->recent(filter))
    records.push_back({{"unix_ms", record.unix_ms},
                       {"time", iso8601_utc(record.unix_ms)},
                       {"door", record.origin.door},
                       {"who", record.origin.who},
                       {"sensor", record.sensor},
                       {"setting", record.setting},
                       {"old", record.old_value},
                       {"new", record.new_value},
                       {"result", record.result}});
  return json_reply(200, json{{"records", std::move(records)}});
}

}  // namespace tiltgate
