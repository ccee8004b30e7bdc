#include "commission/commission_bus.h"

#include "device_server/port_url.h"
#include "device_server/serial_line_maker.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include "control/setting_claim.h"
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

// The bus through a running gateway's control socket when one there serves the tty; none when
// no gateway does (the command then opens the tty itself), unless --via-gateway required one.
// What there is to tell of it goes to `notes`.
Expected<std::unique_ptr<RemoteLine>, CommissionBus::OpenError> bus_through_gateway(
    boost::asio::any_io_executor executor, const CommissionTarget& target,
    std::vector<std::string>& notes) {
  if (target.control_socket.empty()) return std::unique_ptr<RemoteLine>{};
  auto remote = RemoteLine::connect(executor, target.control_socket, target.bus.port);
  if (!remote) {
    const bool elsewhere = remote.error().kind != RemoteLine::ConnectError::failed;
    if (!target.via_gateway && elsewhere) return std::unique_ptr<RemoteLine>{};
    return Unexpected{CommissionBus::OpenError{1, remote.error().message}};
  }
  if (!target.audit_as.empty())
    if (auto acting = (*remote)->act_for(target.audit_as); !acting)
      return Unexpected{CommissionBus::OpenError{1, "--audit-as: " + acting.error()}};
  const control::BusGranted& bus = (*remote)->bus();
  if (bus.protocol != target.bus.protocol)
    return Unexpected{CommissionBus::OpenError{
        2, fmt::format("the running gateway's bus {} on {} speaks {}, not {} (--protocol)",
                       bus.name, target.bus.port, bus.protocol, target.bus.protocol)}};
  notes.push_back(fmt::format("through the running gateway: bus {} ({} baud), control socket {}",
                              bus.name, bus.baud, target.control_socket));
  if (bus.baud != target.bus.baud)
    notes.push_back(fmt::format("note: the gateway runs {} at {} baud; that rate is used, not {}",
                                bus.name, bus.baud, target.bus.baud));
  return std::move(*remote);
}

}  // namespace

CommissionBus::CommissionBus(BusConfig config, FamilyList families, int lock_fd)
    : config_(std::move(config)), families_(families), lock_fd_(lock_fd) {}

CommissionBus::~CommissionBus() {
  stop();
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void CommissionBus::stop() {
  if (serial_) serial_->stop();
  if (remote_) remote_->stop();
  if (served_) served_->stop();
}

std::optional<std::string> CommissionBus::address_changing(std::uint32_t from) {
  if (served_) served_->hold(from);
  if (!remote_) return std::nullopt;
  if (const auto held = remote_->hold(from); !held)
    return fmt::format("the gateway was not told of the move ({}): its polls of the sensor may "
                       "fail while it moves",
                       held.error());
  return std::nullopt;
}

Expected<std::string, std::string> CommissionBus::address_changed(std::uint32_t from,
                                                                  std::uint32_t to) {
  if (served_) served_->follow(from, to);
  if (!remote_) return std::string();
  auto followed = remote_->follow(from, to);
  if (!followed)
    return Unexpected{fmt::format("the gateway was not told of the move: {}; it follows the "
                                  "sensor after a restart with the new address in its "
                                  "configuration",
                                  followed.error())};
  return std::move(*followed);
}

std::optional<std::string> CommissionBus::setting_changed(
    std::uint32_t address, WriteTarget setting, double value, const WriteResult& result,
    std::optional<std::uint8_t> refusal_code) {
  if (!remote_ && !served_) return std::nullopt;
  control::SettingChanged changed{address, setting.id, value, std::nullopt, false};
  if (!result) {
    const WriteError& error = result.error();
    if (error.kind == WriteErrorKind::no_response)
      changed.timeout = true;
    else if (error.kind == WriteErrorKind::device_exception)
      changed.nak = error.device_exception;
    else if (error.kind == WriteErrorKind::rejected || error.kind == WriteErrorKind::refused)
      changed.nak = refusal_code.value_or(0);
    else
      return std::nullopt;  // not the sensor's answer: nothing was changed, nor refused by it
  }
  if (served_) {
    served_->setting_changed(address, setting, value, control::setting_result(changed), true);
    return std::nullopt;
  }
  if (const auto told = remote_->setting_changed(changed); !told)
    return fmt::format("the gateway was not told of the change: {}; its holding registers show "
                       "the setting's old value",
                       told.error());
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
  std::vector<std::string> notes;
  auto remote = bus_through_gateway(executor, target, notes);
  if (!remote) return Unexpected{remote.error()};
  if (*remote) {
    std::unique_ptr<CommissionBus> bus(new CommissionBus(target.bus, target.families, -1));
    bus->opening_notes_ = std::move(notes);
    bus->sensors_ = std::move(*sensors);
    bus->config_.baud = (*remote)->bus().baud;
    bus->remote_ = remote->get();
    bus->remote_->set_defaults({target.bus.timeout, target.bus.retries, target.bus.late_guard});
    bus->line_ = std::move(*remote);
    return bus;
  }
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
  if (remote_ || served_)
    return Unexpected{fmt::format("the running gateway keeps bus {} at {} baud; another rate "
                                  "needs the tty: stop the gateway first",
                                  remote_ ? remote_->bus().name : served_->bus().config.name,
                                  config_.baud)};
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
  return fmt::format(
      "no reply from address {} on {} at {} baud ({})\n"
      "hint: check the baud rate (--baud), the address (--address), the protocol (--protocol) "
      "and the wiring (A/B swapped, termination, power)",
      sensor.config.address, config_.port, config_.baud, config_.protocol);
}

}  // namespace tiltgate
