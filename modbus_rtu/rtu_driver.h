// A Modbus RTU slave described by a device profile (modbus_rtu/device_profile.h), as a sensor:
// each poll reads every [[read]] block (FC 3/4; but those holding identity values only, below),
// decodes the profile's values and publishes a Reading with angle_x and angle_y (NaN when the
// profile has none). Every profile value is published too (Reading::device_values, in profile
// order), for map points to show. An exception reply is the device refusing the request: it is
// counted by its code (refusals[], last_refusal) and fails the poll.
//
// The profile's [identity] values (serial, firmware, model) are read with the blocks that hold
// them at start, after the line reopens and whenever the device answers again after being
// offline (it may have been replaced): a block that holds identity values only is read then,
// not every poll.
//
// The same driver serves devices that speak Modbus TCP themselves (protocol "modbus-tcp"): its
// requests then travel as MBAP frames, the slave being the unit id (modbus_rtu/adu_framing.h).
//
// The profile's writable values are the driver's settings (WriteTarget::device_value(index)):
// a write is checked against the value's range, sent with FC 6 (one register) or FC 16, and
// answered once the device has replied; the device's exception is relayed with its own code.
#pragma once

#include <cstdint>
#include <string>

#include "driver/polled_sensor_driver.h"
#include "modbus_rtu/adu_framing.h"
#include "modbus_rtu/device_profile.h"

namespace tiltgate::modbus_rtu {

struct RtuDriverOptions {
  std::string name;        // the configured sensor name, for log lines
  std::uint8_t slave = 1;  // 1..247 on a serial line; a unit id 0..255 over MBAP
  DeviceProfile profile;
  ReplyTimeouts reply_timeouts;
  Adu adu = Adu::rtu;                   // the bus's protocol's framing
  std::string_view model = "modbus-rtu";  // a ModelDescriptor name (static storage)
};

class RtuDriver final : public PolledSensorDriver {
 public:
  explicit RtuDriver(RtuDriverOptions options);

  std::string_view model() const override { return options_.model; }
  WriteResult check_write(WriteTarget target, double value) const override;
  boost::asio::awaitable<WriteResult> write(Line& line, WriteTarget target, double value) override;
  void follow_address(std::uint32_t address) override;
  // "exception 2 (illegal data address)".
  std::string refusal_text(std::uint8_t code) const override;

 protected:
  boost::asio::awaitable<bool> read_identity(Line& line) override;
  boost::asio::awaitable<void> read_measurement(Line& line) override;
  const std::string& log_name() const override { return options_.name; }
  const char* kind() const override { return "slave"; }

 private:
  // One read block's registers, or nullopt when the exchange failed or the device refused it.
  boost::asio::awaitable<std::optional<std::vector<std::uint16_t>>> read_block(
      Line& line, const ReadBlock& block);
  // One exchange with the device, counted, for the request `build(slave)` makes (a codec
  // builder, AduFraming::exchange); the checked reply, or why there is none.
  template <class Build>
  boost::asio::awaitable<Expected<Reply, WriteError>> exchange(Line& line, Build build);
  boost::asio::awaitable<Expected<Reply, WriteError>> exchange(Line& line,
                                                               ModbusReplyFramer& framer);
  void count_refusal(std::uint8_t code);
  // The identity's strings from the registers just read.
  void take_identity(const PolledBlocks& blocks);

  RtuDriverOptions options_;
  AduFraming framing_;
  // Per read block: whether it holds an identity value, and whether it is polled with every
  // measurement (all blocks but those holding identity values only).
  std::vector<bool> identity_block_;
  std::vector<bool> polled_block_;
  // The registers of the blocks read with the identity only, for the values they hold.
  PolledBlocks identity_registers_;
};

}  // namespace tiltgate::modbus_rtu
