// A sensor's settings through the console (docs/web-console.md, "The API"): GET lists the
// settings its register map writes, with the label, the role and a command's actions its
// family gives each, and the value the gateway knows (read back, or last written: read_back); POST changes one by name through the settings room's writer (settings/setting_writer.h),
// answered once the sensor has: 200 ACK, 409 NAK, 504 time-out, 400 refused, 403 for a role
// that may not (recorded in the audit trail; the writer records the others).
//
// Threads: the buses' executor only, where the sensors and their maps live.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <string>

#include "accounts/role.h"
#include "audit/audit_trail.h"
#include "console/console_requests.h"
#include "driver/family.h"
#include "http/http_routes.h"

namespace tiltgate {

class Gateway;
struct GatewaySensor;

class SettingsEndpoint {
 public:
  SettingsEndpoint(const Gateway* gateway, FamilyList families, AuditTrail* audit)
      : gateway_(gateway), families_(families), audit_(audit) {}

  HttpReply list(const std::string& sensor) const;
  boost::asio::awaitable<HttpReply> change(std::string sensor, SettingRequest asked,
                                           std::string user, Role role) const;

 private:
  std::shared_ptr<GatewaySensor> find(const std::string& name) const;

  const Gateway* gateway_;
  FamilyList families_;
  AuditTrail* audit_;
};

}  // namespace tiltgate
