// A change of one sensor setting by name, as every door asks for it (a Sparkplug DCMD, the
// console's POST /api/sensors/NAME/settings): planned against the sensor's register map with
// the same range checks as a Modbus write of that setting (mapping/map_access.h
// plan_point_write), checked against the bus (another device answering at the address, an
// address another sensor has), queued on the sensor's bus as one SensorWrite
// (line_scheduling/sensor_write.h) with [server] write_timeout, and answered only once the sensor
// acknowledged it, refused it or did not answer (settings/setting_outcome.h).
//
// Who may change which setting is the caller's to decide first (SensorSetting::role,
// settings/sensor_settings.h).
//
// Threads: the gateway's event loop (the buses' executor).
#pragma once

#include <boost/asio/awaitable.hpp>
#include <string>

#include "audit/audit_record.h"
#include "driver/family.h"
#include "gateway/gateway.h"
#include "settings/setting_outcome.h"

namespace tiltgate {

class SettingWriter {
 public:
  SettingWriter(const Gateway& gateway, FamilyList families);

  // Writes `value` (as a user types it) to the setting `setting` of the sensor named `sensor`,
  // for `origin`. The outcome's old_value is the setting as the sensor held it just before.
  boost::asio::awaitable<SettingOutcome> write(std::string sensor, std::string setting,
                                               double value, WriteOrigin origin) const;

 private:
  const Gateway& gateway_;
  FamilyList families_;
};

}  // namespace tiltgate
