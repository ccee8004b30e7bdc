#include "gateway/commission_bus.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include "gateway/driver_registry.h"
#include "gateway/serial_options.h"

namespace tiltgate {

namespace {

// Opens the tty once up front, so that a missing or forbidden one is reported with the
// system's reason instead of being retried in the background as the gateway does, and takes
// an advisory lock on it so that two commissioning commands do not talk over each other.
Expected<int, std::string> open_and_lock(const std::string& port) {
  const int fd = ::open(port.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return Unexpected{fmt::format("cannot open {}: {}", port, std::strerror(errno))};
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EWOULDBLOCK)
      return Unexpected{fmt::format("{} is in use: another tiltgate command holds it", port)};
    return Unexpected{fmt::format("cannot lock {}: {}", port, std::strerror(error))};
  }
  return fd;
}

}  // namespace

CommissionBus::CommissionBus(BusConfig config, int lock_fd)
    : config_(std::move(config)), lock_fd_(lock_fd) {}

CommissionBus::~CommissionBus() {
  if (line_) line_->stop();
  ::close(lock_fd_);
}

Expected<std::unique_ptr<CommissionBus>, CommissionBus::OpenError> CommissionBus::open(
    boost::asio::any_io_executor executor, const CommissionTarget& target) {
  std::vector<CommissionedSensor> sensors;
  for (const SensorConfig& sensor : target.sensors) {
    auto driver = make_driver(sensor, target.bus);
    if (!driver)
      return Unexpected{OpenError{
          2, fmt::format("sensor \"{}\": no driver for model {} on a {} bus", sensor.name,
                         sensor.model, target.bus.protocol)}};
    sensors.push_back({sensor, std::move(driver)});
  }
  auto lock = open_and_lock(target.bus.port);
  if (!lock) return Unexpected{OpenError{1, lock.error()}};
  std::unique_ptr<CommissionBus> bus(new CommissionBus(target.bus, *lock));
  bus->sensors_ = std::move(sensors);
  bus->executor_ = executor;
  bus->line_ = std::make_unique<SerialLine>(executor, serial_options_from(target.bus));
  if (!bus->line_->start())
    return Unexpected{OpenError{1, fmt::format("cannot open {} as a serial port", target.bus.port)}};
  return bus;
}

Expected<Done, std::string> CommissionBus::reopen_at_baud(std::uint32_t baud) {
  line_->stop();
  config_.baud = baud;
  line_ = std::make_unique<SerialLine>(executor_, serial_options_from(config_));
  if (!line_->start()) return Unexpected{fmt::format("cannot reopen {} at {} baud", config_.port, baud)};
  return Done{};
}

std::string CommissionBus::no_reply_message(const CommissionedSensor& sensor) const {
  return fmt::format(
      "no reply from address {} on {} at {} baud ({})\n"
      "hint: check the baud rate (--baud), the address (--address), the protocol (--protocol) "
      "and the wiring (A/B swapped, termination, power)",
      sensor.config.address, config_.port, config_.baud, config_.protocol);
}

}  // namespace tiltgate
