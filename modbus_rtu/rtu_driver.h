// A Modbus RTU slave described by a device profile (modbus_rtu/device_profile.h), as a sensor:
// each poll reads every [[read]] block (FC 3/4), decodes the profile's values and publishes a
// Reading with angle_x and angle_y (NaN when the profile has none). There is no identity to
// read. An exception reply is the device refusing the request: it is counted by its code
// (refusals[], last_refusal) and fails the poll. Writes are refused as not supported: writable
// profile values as settings are the next step.
#pragma once

#include <cstdint>
#include <string>

#include "driver/polled_sensor_driver.h"
#include "modbus_rtu/device_profile.h"

namespace tiltgate::modbus_rtu {

struct RtuDriverOptions {
  std::string name;        // the configured sensor name, for log lines
  std::uint8_t slave = 1;  // 1..247
  DeviceProfile profile;
  ReplyTimeouts reply_timeouts;
};

class RtuDriver final : public PolledSensorDriver {
 public:
  explicit RtuDriver(RtuDriverOptions options);

  std::string_view model() const override { return "modbus-rtu"; }
  WriteResult check_write(WriteTarget target, double value) const override;
  boost::asio::awaitable<WriteResult> write(Line& line, WriteTarget target, double value) override;

 protected:
  boost::asio::awaitable<bool> read_identity(Line& line) override;
  boost::asio::awaitable<void> read_measurement(Line& line) override;
  const std::string& log_name() const override { return options_.name; }
  const char* kind() const override { return "slave"; }

 private:
  // One read block's registers, or nullopt when the exchange failed or the device refused it.
  boost::asio::awaitable<std::optional<std::vector<std::uint16_t>>> read_block(
      Line& line, const ReadBlock& block);

  RtuDriverOptions options_;
};

}  // namespace tiltgate::modbus_rtu
