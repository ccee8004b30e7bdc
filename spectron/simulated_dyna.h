// A model of one SPECTROTILT Dyna module on the bus, answering either protocol as the
// application note describes (with the reply formats of spectron/assumptions.h). Pure: time
// is passed in (seconds since the simulation started), so tests are deterministic.
//
// Choices where the note is silent (documented here and tested):
// - The EEPROM holds the even locations 0..280. Reads of other locations, writes of other
//   locations or of values the map does not allow (a module address out of the protocol's
//   range, a baud code not in the table) get no reply, as does anything it does not parse:
//   the note defines no error reply.
// - Writes are not protected: the gateway decides what it writes (eeprom::check_value).
// - A write to location 16 is answered from the old address; the module answers at the new one
//   from the next request. Offsets (6, 10) apply at once. A new baud code (22) takes effect at
//   the next reset, like a UART that is configured at start-up. Reset (command or power cycle)
//   re-reads the module address and the baud code from the EEPROM.
// - The reading is raw counts minus the sensor offset (location 6, as a signed word), the
//   temperature raw minus the temperature offset (location 10); both are clamped to a signed
//   16-bit word, the size a Modbus-ASCII reply carries (A6).
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spectron/ascii_codec.h"
#include "spectron/eeprom_map.h"
#include "spectron/nine_bit_codec.h"
#include "spectron/protocol.h"

namespace tiltgate::spectron {

struct SimulatedDynaOptions {
  std::uint8_t address = 0;             // EEPROM 16; "Module address = 0 (factory set)"
  std::uint16_t serial = 12345;         // EEPROM 4
  std::string firmware = "DYNA 1.07";   // the 9-bit "F" reply
  std::uint16_t revision = 0x0107;      // the Modbus-ASCII 0x6A word, shown "01.07"
  // Raw counts: base + amplitude * sin(2 pi t / period); zero amplitude keeps them fixed.
  std::int16_t counts = 1000;
  double sway_amplitude = 0.0;
  double sway_period_s = 20.0;
  std::int16_t temperature = 250;  // raw temperature
  int baud_code = 10;              // EEPROM 22: 28800, the rate of the note's example
};

// Faults of one command only. The Dyna has no NAKs: it can only stay silent or answer late.
struct CommandFaults {
  int silent = 0;  // answer nothing to this many requests of the command (no effect either)
  // Answer every request of the command this much later (on top of DynaFaults::reply_delay).
  std::chrono::milliseconds delay{0};
};

// Faults a test can inject. silent counts requests addressed to this module; corrupt_lrc and
// garbage count replies. The whole-module faults apply before by_command's.
struct DynaFaults {
  int silent = 0;       // answer nothing
  int corrupt_lrc = 0;  // Modbus-ASCII only: change the LRC's last digit (9-bit has no check)
  int garbage = 0;      // send garbage_bytes before the reply
  // Line noise: none of these is printable or ':', so both protocols' parsers drop them.
  std::vector<std::uint8_t> garbage_bytes = {0x00, 0xFF, 0x13, 0x80};
  // Answer everything this much later: a slow module, or a slow adapter in between.
  std::chrono::milliseconds reply_delay{0};
  // Keyed by the Modbus-ASCII command; a 9-bit command counts as its counterpart ("A" as
  // read_sensor, "F" as revision, and so on).
  std::map<AsciiCommand, CommandFaults> by_command;
};

// The Modbus-ASCII command a 9-bit command corresponds to.
AsciiCommand counterpart(NineBitCommand command);

class SimulatedDyna {
 public:
  explicit SimulatedDyna(SimulatedDynaOptions options);

  // 9-bit addressing: the reply to `body` (without its CR LF) sent after address byte
  // `address`, with faults applied; nullopt is silence.
  std::optional<std::vector<std::uint8_t>> respond_nine_bit(std::uint8_t address,
                                                            std::string_view body, SimTime now);
  // Modbus-ASCII: the reply to a good frame, encoded, with faults applied; nullopt is silence.
  std::optional<std::vector<std::uint8_t>> respond_ascii(const AsciiFrame& request, SimTime now);

  // Power cycle: what the reset command does, without a request.
  void reset();

  // What a read would report at `now`, offsets subtracted.
  std::int16_t counts(SimTime now) const;
  std::int16_t temperature() const;
  void set_counts(std::int16_t counts);  // fixed raw counts from now on
  void set_serial(std::uint16_t serial);  // another module put in its place (EEPROM 4)
  void set_motion(double amplitude, double period_s);
  void set_temperature(std::int16_t raw);

  DynaFaults& faults() { return faults_; }
  // How much later than usual this module answers `command` (the simulator waits).
  std::chrono::milliseconds reply_delay(AsciiCommand command) const;

  std::uint8_t address() const { return address_; }  // the address it answers at
  int baud_code() const { return baud_code_; }        // the code in effect
  // The word at `location`, or nullopt outside the EEPROM (odd, or past 280). Every word it
  // holds is answered to a read, reserved ones included.
  std::optional<std::uint16_t> eeprom(std::int64_t location) const;
  // Stores a word as a service tool on another port would, behind the gateway's back (no
  // checks, no move to a new address); false outside the EEPROM.
  bool set_eeprom(std::int64_t location, std::uint16_t value);
  const std::string& firmware() const { return options_.firmware; }
  std::uint16_t revision() const { return options_.revision; }
  std::uint64_t requests_handled() const { return requests_handled_; }
  std::uint64_t resets() const { return resets_; }

 private:
  // Counts the request and applies the silent faults: false when it must go unanswered.
  bool accept_request(AsciiCommand command);
  // Stores `value`; false (and nothing stored) when the location or value is not accepted.
  bool write(std::int64_t location, std::uint16_t value, Protocol protocol);
  std::vector<std::uint8_t> with_garbage(std::vector<std::uint8_t> bytes);

  static constexpr std::size_t kWords = eeprom::kReservedLast / 2 + 1;  // locations 0..280

  SimulatedDynaOptions options_;
  std::array<std::uint16_t, kWords> eeprom_{};
  std::uint8_t address_;
  int baud_code_;
  DynaFaults faults_;
  std::uint64_t requests_handled_ = 0;
  std::uint64_t resets_ = 0;
};

}  // namespace tiltgate::spectron
