// The SPECTROTILT Dyna driver, for both of its protocols (9-bit addressing and Modbus-ASCII):
// turns polls and register writes into Dyna transactions (spectron/dyna_transactions.h).
//
// A poll reads the raw sensor counts and the raw temperature; the counts become degrees, and the
// temperature degrees Celsius, by the sensor's configured linear conversions, because the
// application note gives none. Identity
// (firmware revision, serial number from EEPROM 4) is read at start, after every reconnect of
// the line and after a reset. Settings are EEPROM writes: the named offsets (6, 10, 20), the
// module address (16; the driver follows the module), the baud code (22; in force after the
// next reset, so the bus's baud must follow), and any other writable location through an
// EEPROM window (select a location, then write its value). The Dyna has no NAKs and no locks.
//
// The settings are read back from the EEPROM ("3" / 0x69) with the identity and after every
// write, and published in SensorState::settings, so a holding register shows what the module
// holds; selecting a window location reads that location.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "driver/polled_sensor_driver.h"
#include "spectron/dyna_transactions.h"
#include "spectron/protocol.h"
#include "spectron/setting_ids.h"

namespace tiltgate::spectron {

struct DynaDriverOptions {
  std::string name = "sensor";  // for log lines
  Protocol protocol = Protocol::nine_bit;
  int address = 0;  // 0..255 on a 9-bit bus ("Module address = 0 (factory set)"), 1..250 on Modbus
  // degrees = (counts - zero_counts) / counts_per_degree ([[sensor]] keys of the same name).
  double counts_per_degree = 100.0;
  double zero_counts = 0.0;
  // degC = (temperature counts - temperature_zero_counts) / temperature_counts_per_degree:
  // the note gives no conversion either; 10 counts per degree (0.1 degC) is the assumption
  // written down in docs/protocols.md, "Dyna: what the note leaves open".
  double temperature_counts_per_degree = 10.0;
  double temperature_zero_counts = 0.0;
  // Quiet time after a reset before the next request. The note does not say how long the
  // processor takes to restart; a module that takes longer only costs one timed-out poll.
  std::chrono::milliseconds reset_settle{200};
  ReplyTimeouts reply_timeouts;  // the bus's timeout_ms and max_timeout_ms
  // [[sensor]] eeprom_reserved_writes: the EEPROM window may write the reserved block 100..280
  // (the note's own example writes there); off by default.
  bool reserved_writes = false;
};

// Why one exchange produced no usable reply.
struct ExchangeError {
  enum class Kind {
    line,         // no reply (time-out, port failure)
    bad_reply,    // a reply that does not answer the request as expected
    bad_request,  // the protocol cannot carry the request (nothing was sent)
  } kind;
  LineError line = LineError::timeout;
  std::string detail;
};

class DynaDriver : public PolledSensorDriver {
 public:
  explicit DynaDriver(DynaDriverOptions options);

  std::string_view model() const override { return "dyna"; }
  // Checks every value against the memory map; an eeprom_value against the location selected
  // now (write() checks it again against the one selected when it runs).
  WriteResult check_write(WriteTarget target, double value) const override;
  // Also an EEPROM window write while the module address location is selected.
  std::optional<std::uint32_t> address_after(WriteTarget target, double value) const override;
  // As check_write, but an eeprom_value against the location the request selects before it.
  WriteResult check_writes(std::span<const SettingWrite> writes) const override;
  // A location selected by the failed request is unselected again.
  void abandon(std::span<const SettingWrite> done) override;
  boost::asio::awaitable<WriteResult> write(Line& line, WriteTarget target, double value) override;

  void follow_address(std::uint32_t address) override;

  int address() const { return options_.address; }
  // The EEPROM window's location (setting::eeprom_location), none until one is written.
  std::optional<std::uint16_t> eeprom_location() const;

 protected:
  boost::asio::awaitable<bool> read_identity(Line& line) override;
  boost::asio::awaitable<void> read_measurement(Line& line) override;  // sensor, temperature
  // EEPROM read-back: every named setting and the window's location; false when the module
  // stopped answering.
  boost::asio::awaitable<bool> read_settings(Line& line) override;
  const std::string& log_name() const override { return options_.name; }
  const char* kind() const override { return "Dyna"; }

 private:
  // One request to the module at `address` (default: the configured one) and its reply, with
  // the counters kept.
  boost::asio::awaitable<Expected<DynaAnswer, ExchangeError>> exchange(
      Line& line, DynaRequest request, ExchangeOptions options = {},
      std::optional<int> address = std::nullopt);
  void failed_measurement(const ExchangeError& error);
  // Writes `value` to EEPROM `location`, already checked; location 16 moves the module.
  boost::asio::awaitable<WriteResult> write_location(Line& line, std::uint16_t location,
                                                     std::uint16_t value);
  boost::asio::awaitable<WriteResult> set_address(Line& line, int new_address);
  boost::asio::awaitable<WriteResult> reset(Line& line);
  // Selects the window's location, reading it from the module; the selection stays as it was
  // when the module does not answer.
  boost::asio::awaitable<WriteResult> select_location(Line& line, std::uint16_t location);
  WriteResult check_location_value(std::int64_t location, double value) const;
  WriteResult check_window_value(std::optional<std::uint16_t> location, double value) const;

  // Reads one location and publishes it in state_.settings (unknown if unreadable).
  boost::asio::awaitable<Expected<std::uint16_t, ExchangeError>> read_back(Line& line,
                                                                           std::uint16_t location);
  void publish(std::uint16_t location, std::optional<std::uint16_t> value);

  // The window's selection before the last location write, for abandon().
  struct WindowSelection {
    std::optional<double> location;
    std::optional<double> value;
  };

  DynaDriverOptions options_;
  WindowSelection selection_before_;
};

// An ExchangeError as the write error the gateway maps to a Modbus exception: no reply is
// no_response (0x0B), a reply that is not the expected acknowledgement is refused (0x04), a
// request the protocol cannot carry is bad_value (0x03).
WriteError to_write_error(const ExchangeError& error, std::string_view step);

}  // namespace tiltgate::spectron
