#include "commission/commission_bus.h"

#include "device_server/port_url.h"
#include "device_server/serial_line_maker.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include "audit/audit_trail.h"
#include "gateway/driver_registry.h"
#include "gateway/serial_options.h"

namespace tiltgate {

namespace {

// Opens the tty once up front, so that a missing or forbidden one is reported with the
// system's reason instead of being retried in the background as the gateway does, and takes
// an advisory lock on it so that two commissioning commands do not talk over each other.
Expected<int, std::string> open_and_lock(const std::string& port) {
  // A device server's port has no file to lock: the server itself takes one client at a time.
  if (looks_like_url(port)) return -1;
  const int fd = ::open(port.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return Unexpected{fmt::format("cannot open {}: {}", port, std::strerror(errno))};
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EWOULDBLOCK)
      return Unexpected{fmt::format(
          "{} is in use: a running gateway or another tiltgate command holds it (a gateway "
          "with a control socket is used through it: see --via-gateway)",
          port)};
    return Unexpected{fmt::format("cannot lock {}: {}", port, std::strerror(error))};
  }
  return fd;
}

}  // namespace

std::string device_server_failure_text(const std::string& port, const PortFailure& failure) {
  const auto url = parse_port(port);
  const std::string server = url ? url->endpoint() : port;
  if (failure.kind == PortFailure::Kind::other)
    return fmt::format("cannot connect to the device server at {} ({})", server, failure.why);
  return fmt::format(
      "the device server at {} {} the connection ({}): the port is probably held by a running "
      "gateway or another client; stop it, or run the command through the gateway's control "
      "socket (--via-gateway)",
      server, failure.kind == PortFailure::Kind::refused ? "refused" : "closed", failure.why);
}

CommissionBus::CommissionBus(BusConfig config, FamilyList families, int lock_fd)
    : config_(std::move(config)), families_(families), lock_fd_(lock_fd) {}

CommissionBus::~CommissionBus() {
  stop();
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void CommissionBus::stop() {
  if (serial_) serial_->stop();
  if (served_) served_->stop();
}

std::optional<std::string> CommissionBus::address_changing(std::uint32_t from) {
  if (served_) served_->hold(from);
  return std::nullopt;
}

Expected<std::string, std::string> CommissionBus::address_changed(std::uint32_t from,
                                                                  std::uint32_t to) {
  if (!served_) return std::string();
  const auto followed = served_->follow(from, to);
  return followed ? served_->bus().config.name + "/" + *followed : std::string();
}

std::optional<std::string> CommissionBus::setting_changed(
    std::uint32_t address, WriteTarget setting, double value, const WriteResult& result,
    std::optional<std::uint8_t> refusal_code) {
  if (!served_) return std::nullopt;
  // As the audit trail words a setting's outcome (audit/audit_record.h).
  std::string outcome = "ack";
  if (!result) {
    const WriteError& error = result.error();
    if (error.kind == WriteErrorKind::no_response)
      outcome = "timeout";
    else if (error.kind == WriteErrorKind::device_exception)
      outcome = fmt::format("nak 0x{:02X}", error.device_exception);
    else if (error.kind == WriteErrorKind::rejected || error.kind == WriteErrorKind::refused)
      outcome = fmt::format("nak 0x{:02X}", refusal_code.value_or(0));
    else
      return std::nullopt;  // not the sensor's answer: nothing was changed, nor refused by it
  }
  served_->setting_changed(address, setting, value, std::move(outcome));
  return std::nullopt;
}

Expected<std::vector<CommissionedSensor>, CommissionBus::OpenError> CommissionBus::make_sensors(
    const CommissionTarget& target) {
  std::vector<CommissionedSensor> sensors;
  for (const SensorConfig& sensor : target.sensors) {
    if (target.without_drivers) {
      sensors.push_back({sensor, nullptr, target.model_source});
      continue;
    }
    auto driver = make_driver(target.families, sensor, target.bus);
    if (!driver)
      return Unexpected{OpenError{
          2, fmt::format("sensor \"{}\": no driver for model {} on a {} bus", sensor.name,
                         sensor.model, target.bus.protocol)}};
    sensors.push_back({sensor, std::move(driver), target.model_source});
  }
  return sensors;
}

Expected<std::unique_ptr<CommissionBus>, CommissionBus::OpenError> CommissionBus::open(
    boost::asio::any_io_executor executor, const CommissionTarget& target) {
  auto sensors = make_sensors(target);
  if (!sensors) return Unexpected{sensors.error()};
  auto lock = open_and_lock(target.bus.port);
  if (!lock) return Unexpected{OpenError{1, lock.error()}};
  std::unique_ptr<CommissionBus> bus(new CommissionBus(target.bus, target.families, *lock));
  bus->sensors_ = std::move(*sensors);
  bus->executor_ = executor;
  if (auto started = bus->start_line(); !started) return Unexpected{OpenError{1, started.error()}};
  return bus;
}

Expected<std::unique_ptr<CommissionBus>, CommissionBus::OpenError> CommissionBus::on_served_line(
    const CommissionTarget& target, std::unique_ptr<ServedBusLine> line) {
  auto sensors = make_sensors(target);
  if (!sensors) return Unexpected{sensors.error()};
  std::unique_ptr<CommissionBus> bus(new CommissionBus(target.bus, target.families, -1));
  bus->sensors_ = std::move(*sensors);
  bus->config_.baud = line->bus().config.baud;
  bus->served_ = line.get();
  bus->served_->set_defaults({target.bus.timeout, target.bus.retries, target.bus.late_guard});
  bus->line_ = std::move(line);
  return bus;
}

Expected<Done, std::string> CommissionBus::start_line() {
  auto line = make_serial_line(executor_, serial_options_from(families_, config_));
  serial_ = line.get();
  line_ = std::move(line);
  // A device server's connection is being made: the first exchange waits for it.
  if (!serial_->start() && !serial_->opening()) return Unexpected{fmt::format("cannot open {} as a serial port", config_.port)};
  return Done{};
}

Expected<Done, std::string> CommissionBus::reopen_at(std::uint32_t baud) {
  // The running gateway's bus stays at its rate: its other sensors are set to it.
  if (served_)
    return Unexpected{fmt::format("the running gateway keeps bus {} at {} baud; another rate "
                                  "needs the tty: stop the gateway first",
                                  served_->bus().config.name, config_.baud)};
  // Over raw TCP the far port's rate is the device server's own setting.
  if (const auto port = parse_port(config_.port); port && port->scheme == PortScheme::tcp)
    return Unexpected{fmt::format("{} is raw TCP: the device server keeps its port at {} baud "
                                  "(its own setting); set it to {} on the server, or use "
                                  "rfc2217://{}, which the gateway sets",
                                  config_.port, config_.baud, baud, port->endpoint())};
  serial_->stop();
  config_.baud = baud;
  return start_line();
}

std::string CommissionBus::no_reply_message(const CommissionedSensor& sensor) const {
  if (served_ && served_->last_audit_refused())
    return fmt::format("not sent to address {} on {}: {}", sensor.config.address,
                       served_->bus().config.name, kAuditRefusesChanges);
  // In the gateway the tty is the gateway's: one it cannot open is its line's fault, not the
  // sensor's, and its log says why.
  if (served_ && !served_->bus().scheduler->line().is_open())
    return fmt::format("nothing sent to address {}: the gateway's bus {} on {} is not open "
                       "(the gateway's log says why: a missing or unplugged adapter, a device "
                       "server out of reach)",
                       sensor.config.address, served_->bus().config.name, config_.port);
  // Over a device server the command's own connection may be what failed, not the sensor:
  // a server turns a second client of a port away (docs/operations.md, "Serial device
  // servers"), and what it said is the answer, not a wiring hint.
  if (serial_ && !serial_->is_open())
    if (const std::optional<PortFailure> failure = serial_->connection_failure())
      return device_server_failure_text(config_.port, *failure);
  return fmt::format(
      "no reply from address {} on {} at {} baud ({})\n"
      "hint: check the baud rate (--baud), the address (--address), the protocol (--protocol) "
      "and the wiring (A/B swapped, termination, power)",
      sensor.config.address, config_.port, config_.baud, config_.protocol);
}

}  // namespace tiltgate
