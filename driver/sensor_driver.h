// The interface between the gateway core and a vendor's sensors. The core schedules; a driver
// turns "poll now" and "write this setting" into protocol transactions on a Line and keeps the
// SensorState the register map reads. Only drivers know a vendor.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "driver/expected.h"
#include "driver/line.h"
#include "driver/sensor_state.h"
#include "driver/write_target.h"

namespace tiltgate {

// Values of WriteTarget::command.
enum class SensorCommand : std::uint16_t {
  zero_temporary = 1,  // zero to current angle, lost on restart
  zero_permanent = 2,  // zero to current angle, kept
  restart = 3,
};

enum class WriteErrorKind {
  not_supported,   // the sensor has no such setting (Modbus 0x02/0x01)
  bad_value,       // rejected before anything was sent (Modbus 0x03)
  rejected,        // the sensor refused the data (a NAK for bad data; Modbus 0x03)
  refused,         // the sensor refused for another reason (other NAKs; Modbus 0x04)
  busy,            // still busy after the retries (Modbus 0x06)
  no_response,     // time-out or port failure (Modbus 0x0B)
  // A device that speaks Modbus itself refused with an exception: relayed with its own code.
  device_exception,
};

struct WriteError {
  WriteErrorKind kind;
  std::string detail;  // for the log: which step failed and why
  std::uint8_t device_exception = 0;  // kind device_exception: the device's exception code
  // The code the sensor refused the write with, when its protocol has such codes (a NAK's):
  // what the audit trail records (settings/setting_outcome.h). A device exception's is above.
  std::optional<std::uint8_t> nak{};
};

using WriteResult = Expected<Done, WriteError>;

// One setting of a Modbus request that writes several in address order.
struct SettingWrite {
  WriteTarget target;
  double value;
};

class SensorDriver {
 public:
  virtual ~SensorDriver() = default;

  // A ModelDescriptor name of its family (driver/family.h): selects the default register map.
  virtual std::string_view model() const = 0;

  // Whether a value may be written, checked before the write is queued.
  virtual WriteResult check_write(WriteTarget target, double value) const = 0;
  // Whether the settings of one request may be written, in this order, checked before any of
  // them is queued. A driver whose settings depend on each other (an EEPROM window: a value
  // goes to the location selected before it) checks each against those before it.
  virtual WriteResult check_writes(std::span<const SettingWrite> writes) const {
    for (const SettingWrite& w : writes) {
      auto checked = check_write(w.target, w.value);
      if (!checked) return checked;
    }
    return Done{};
  }
  // A request failed after `done`, its first settings, were carried out: take back what only
  // prepared a later one (the EEPROM window's selection). Settings the sensor took stay.
  virtual void abandon(std::span<const SettingWrite> done) { (void)done; }

  // The bus address this write would move the sensor to, if it moves it. The bus refuses one
  // that another of its sensors has, before the write is queued and again when it starts (an
  // earlier write may have moved a sensor, or selected the address for an EEPROM write).
  virtual std::optional<std::uint32_t> address_after(WriteTarget target, double value) const {
    if (target != WriteTarget::bus_address || !(value >= 0 && value <= 0xFFFF'FFFF)) return {};
    return std::uint32_t(value);
  }

  // Someone else moved the sensor to `address` (a commissioning command through the control
  // socket, control/control_server.h): talk to it there from now on. The caller has checked the
  // address against the protocol's range.
  virtual void follow_address(std::uint32_t address) = 0;

  // Someone else changed a setting and the sensor acknowledged it (a commissioning command
  // through the control socket, control/control_server.h): the driver keeps its settings record
  // (SensorState::settings) as after a write() of its own, so that every door (Modbus,
  // Sparkplug, `tiltgate set` through the gateway) shows in the same record. A driver that can
  // read its settings back reads them instead at its next poll; one that keeps no record
  // ignores it.
  virtual void note_acknowledged(WriteTarget target, double value) {
    (void)target;
    (void)value;
  }

  // The serial the device at the sensor's address must report ([[sensor]] serial, trimmed;
  // empty: any). A driver that reads a serial sets SensorState::wrong_device when another one
  // answers there.
  virtual void expect_serial(std::string serial) { (void)serial; }

  // One poll cycle: reads identity first when it is unknown (after start and after the line
  // reopened), then one measurement. Updates state(); never throws.
  virtual boost::asio::awaitable<void> poll(Line& line) = 0;

  // Carry out one write, including any unlocking the protocol needs. Answers only once the
  // sensor has acknowledged (or failed).
  virtual boost::asio::awaitable<WriteResult> write(Line& line, WriteTarget target,
                                                    double value) = 0;

  virtual const SensorState& state() const = 0;
  // Sets state().counters back to zero, as at a start (an admin's reset, Modbus FC 08's clear).
  virtual void reset_counters() = 0;

  // A refusal code of the protocol (SensorCounters::last_refusal) as its manual names it, for
  // the user: "NAK 2 (function not valid for this sensor or mode)".
  virtual std::string refusal_text(std::uint8_t code) const;
};

}  // namespace tiltgate
