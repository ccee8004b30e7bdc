// One bus opened for a commissioning command: its tty, held with an advisory lock for as long
// as the command runs, or its device server's port (tcp://, rfc2217://: one connection, no
// lock), or a command's line on a bus a running gateway serves (control/served_bus_line.h: the
// web console's commands, and those the control socket brings); and a driver for each sensor
// the command talks to. The
// command polls the sensors through their drivers, as the gateway's bus scheduler does, one at
// a time.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "driver/sensor_driver.h"
#include "commission/commission_options.h"
#include "control/served_bus_line.h"
#include "serial/serial_line.h"

namespace tiltgate {

struct CommissionedSensor {
  SensorConfig config;
  // None when the target goes without drivers (CommissionTarget::without_drivers): only the
  // commands that allow it (BusOptions::driver_optional) see such a sensor.
  std::unique_ptr<SensorDriver> driver;
  // Where config.model came from: --model or the configuration decide the driver; a detected
  // one (the protocol's first model until then) is replaced by the model the sensor measures
  // as (commission/model_detection.h).
  ModelSource model_source = ModelSource::configuration;
};

// What a command says when its own connection to a device server (`port`, a URL) failed: the
// server turned it away (the port held by another client: the cure) or could not be reached.
std::string device_server_failure_text(const std::string& port, const PortFailure& failure);

class CommissionBus {
 public:
  // Why the bus cannot be used, for the user; 2 when the options were wrong (no driver for a
  // sensor), 1 when the tty was (missing, not openable, in use).
  struct OpenError {
    int exit_code;
    std::string message;
  };

  static Expected<std::unique_ptr<CommissionBus>, OpenError> open(
      boost::asio::any_io_executor executor, const CommissionTarget& target);
  // The bus a command runs on inside the gateway (the web console's, the control socket's):
  // `line` on the bus the gateway serves, whose baud it keeps. The sensors' drivers are made as open() makes them.
  static Expected<std::unique_ptr<CommissionBus>, OpenError> on_served_line(
      const CommissionTarget& target, std::unique_ptr<ServedBusLine> line);
  ~CommissionBus();
  CommissionBus(const CommissionBus&) = delete;
  CommissionBus& operator=(const CommissionBus&) = delete;

  const BusConfig& config() const { return config_; }
  // The families the bus and its sensors were checked against: every driver is made from them.
  FamilyList families() const { return families_; }
  // The bus's line. Commands talk to sensors only through it (their drivers' transactions or
  // their own), so that the same command also works through a running gateway.
  Line& line() { return *line_; }
  std::vector<CommissionedSensor>& sensors() { return sensors_; }
  // Cancels what is on the line; a suspended poll returns at once.
  void stop();
  // Whether the bus is a running gateway's: the command runs in the gateway.
  bool through_gateway() const { return served_ != nullptr; }

  // A command is about to move the sensor at `from` (set address): a running gateway that
  // owns the bus stops polling it, so that no poll at the old address fails while it moves,
  // until address_changed() or the command's end. Nothing to do on a tty of our own. A warning
  // when the gateway could not be told.
  std::optional<std::string> address_changing(std::uint32_t from);
  // A command moved a sensor from one bus address to another (set address): a running gateway
  // that owns the bus follows it at once. The gateway's name for the sensor it now polls at
  // `to` (empty: none, e.g. on a tty of our own), or a warning when it could not be told.
  Expected<std::string, std::string> address_changed(std::uint32_t from, std::uint32_t to);
  // The sensor at `address` answered a setting (`result`; a refusal with the protocol's code
  // `refusal_code`): a running gateway that owns the bus records it in its audit trail, and
  // keeps an acknowledged one in the sensor's settings record (what its holding registers
  // read). Nothing to do on a tty of our own. A warning when the gateway could not be told.
  std::optional<std::string> setting_changed(std::uint32_t address, WriteTarget setting,
                                             double value, const WriteResult& result,
                                             std::optional<std::uint8_t> refusal_code);

  // Reopens the tty at another baud rate (scan --baud auto; set baud, after the sensor was set
  // to it and restarted), keeping the lock; the bus's config() follows. An error says why it
  // cannot be done (through a running gateway, whose bus keeps its rate).
  Expected<Done, std::string> reopen_at(std::uint32_t baud);


  // "no reply from address 5 on /dev/ttyUSB0 at 125000 baud", and what to check; or, in the
  // gateway, why its line refused to send the request.
  std::string no_reply_message(const CommissionedSensor& sensor) const;

 private:
  CommissionBus(BusConfig config, FamilyList families, int lock_fd);
  // The target's sensors, each with its driver unless the target goes without.
  static Expected<std::vector<CommissionedSensor>, OpenError> make_sensors(
      const CommissionTarget& target);
  Expected<Done, std::string> start_line();

  boost::asio::any_io_executor executor_;
  BusConfig config_;
  FamilyList families_;
  int lock_fd_;  // -1 through a gateway, or on a device server's port
  std::unique_ptr<Line> line_;
  SerialLine* serial_ = nullptr;  // line_, on a tty of our own
  ServedBusLine* served_ = nullptr;  // line_, in the gateway
  std::vector<CommissionedSensor> sensors_;
};

}  // namespace tiltgate
