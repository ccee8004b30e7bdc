// One bus opened for a commissioning command: its tty, held with an advisory lock for as long
// as the command runs, and a driver for each sensor the command talks to. The command polls
// the sensors through their drivers, as the gateway's bus scheduler does, one at a time.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "driver/sensor_driver.h"
#include "gateway/commission_options.h"
#include "serial/serial_line.h"

namespace tiltgate {

struct CommissionedSensor {
  SensorConfig config;
  std::unique_ptr<SensorDriver> driver;
};

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
  ~CommissionBus();
  CommissionBus(const CommissionBus&) = delete;
  CommissionBus& operator=(const CommissionBus&) = delete;

  const BusConfig& config() const { return config_; }
  // The bus's line. Commands talk to sensors only through it (their drivers' transactions or
  // their own), so that the same command also works through a running gateway.
  Line& line() { return *line_; }
  std::vector<CommissionedSensor>& sensors() { return sensors_; }
  // Cancels what is on the line; a suspended poll returns at once.
  void stop() { line_->stop(); }

  // A command moved a sensor from one bus address to another (set address): a running gateway
  // that owns the bus follows it at once. Nothing to do on a tty of our own.
  void address_changed(std::uint32_t from, std::uint32_t to) { (void)from; (void)to; }

  // The line again at another rate, after a sensor was set to it and restarted (set baud). The
  // tty stays locked; on failure the line stays closed.
  Expected<Done, std::string> reopen_at_baud(std::uint32_t baud);

  // "no reply from address 5 on /dev/ttyUSB0 at 125000 baud", and what to check.
  std::string no_reply_message(const CommissionedSensor& sensor) const;

 private:
  CommissionBus(BusConfig config, int lock_fd);

  BusConfig config_;
  int lock_fd_;
  boost::asio::any_io_executor executor_;
  std::unique_ptr<SerialLine> line_;
  std::vector<CommissionedSensor> sensors_;
};

}  // namespace tiltgate
