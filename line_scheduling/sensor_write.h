// One Modbus write request to a cached sensor, as its bus carries it out: the settings the
// request's registers planned (mapping's plan_register_write), written in address order
// through the sensor's driver. The one place that checks a write, logs it, records each of
// its settings in the audit trail (the bus's, audit/audit_trail.h) with who asked for it,
// keeps the holding shadow (GatewaySensor::written) and publishes the snapshot after it.
//
// Threads: the bus's thread only. It holds the sensor: a reload may drop it while the write
// waits for the bus, and the write is still carried out and answered.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "audit/audit_record.h"
#include "driver/line.h"
#include "driver/sensor_driver.h"
#include "line_scheduling/gateway_sensor.h"
#include "mapping/map_access.h"

namespace tiltgate {

class BusScheduler;

class SensorWrite {
 public:
  SensorWrite(std::shared_ptr<GatewaySensor> sensor, std::vector<PlannedWrite> plan,
              WriteOrigin origin);

  // Whether the settings from `first` on may be written now: not while another device answers
  // in the sensor's place (refused, 0x04), the driver's check of their
  // values, together and in order (a value may depend on a setting before it: an EEPROM
  // window's location), and the bus's refusal of an address another of its sensors has.
  WriteResult check(const BusScheduler& bus, std::size_t first = 0) const;
  // check() before the write is queued: a refusal is answered at once, and logged.
  WriteResult admit(const BusScheduler& bus) const;
  // Writes the settings one after another, each checked again as it starts (an earlier
  // write, of this request or another, may have moved a sensor or selected an address since
  // the write was queued), and stops at the first failure, taking back what only prepared a
  // later setting. Updates the holding shadow of each setting written, publishes the snapshot
  // once at the end, and counts each setting it hands to the driver in `sent`.
  boost::asio::awaitable<WriteResult> run(Line& line, const BusScheduler& bus,
                                          std::uint64_t& sent);
  // Answers a write the bus does not carry out (not started before its deadline, the bus
  // stopping, the sensor known offline) with `why`, logged as its first setting's failure.
  WriteResult fail(const BusScheduler& bus, WriteError why) const;

  GatewaySensor& sensor() const { return *sensor_; }

 private:
  boost::asio::awaitable<WriteResult> write_setting(Line& line, const BusScheduler& bus,
                                                    std::size_t index, std::uint64_t& sent);
  void log_failure(std::size_t index, const WriteError& error) const;
  // One setting's record in the bus's trail; `old_value` as the sensor held it before.
  void audit(const BusScheduler& bus, std::size_t index, std::optional<double> old_value,
             std::string result) const;
  // The settings from `first` on, each recorded with `result` (not carried out).
  void audit_rest(const BusScheduler& bus, std::size_t first, const std::string& result) const;

  std::shared_ptr<GatewaySensor> sensor_;
  std::vector<PlannedWrite> plan_;
  std::vector<SettingWrite> settings_;  // plan_'s targets and values, as the driver takes them
  WriteOrigin origin_;
};

}  // namespace tiltgate
