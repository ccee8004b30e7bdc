#include "spectron/simulated_dyna.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "spectron/nine_bit_codec.h"

namespace tiltgate::spectron {
namespace {

std::int16_t clamp_to_word(double value) {
  constexpr double kMin = std::numeric_limits<std::int16_t>::min();
  constexpr double kMax = std::numeric_limits<std::int16_t>::max();
  return static_cast<std::int16_t>(std::clamp(std::round(value), kMin, kMax));
}

// Data bytes each Modbus-ASCII request carries (the note's command list).
std::optional<std::size_t> request_data_bytes(std::uint8_t command) {
  switch (static_cast<AsciiCommand>(command)) {
    case AsciiCommand::reset:
    case AsciiCommand::read_sensor:
    case AsciiCommand::read_temperature:
    case AsciiCommand::revision: return 0;
    case AsciiCommand::read_eeprom: return 2;   // location (4 hex)
    case AsciiCommand::write_eeprom: return 4;  // location (4 hex), data (4 hex)
  }
  return std::nullopt;
}

}  // namespace

SimulatedDyna::SimulatedDyna(SimulatedDynaOptions options)
    : options_(std::move(options)), address_(options_.address), baud_code_(options_.baud_code) {
  eeprom_[eeprom::kSerialNumber / 2] = options_.serial;
  eeprom_[eeprom::kModuleAddress / 2] = options_.address;
  eeprom_[eeprom::kBaudCode / 2] = static_cast<std::uint16_t>(options_.baud_code);
}

std::optional<std::vector<std::uint8_t>> SimulatedDyna::respond_nine_bit(std::uint8_t address,
                                                                         std::string_view body,
                                                                         SimTime now) {
  if (address != address_) return std::nullopt;
  const auto line = parse_nine_bit_body(body);
  if (!line || !accept_request(counterpart(line->command))) return std::nullopt;
  std::string text;  // A4: numbers in decimal; reset and write answer an empty line
  switch (line->command) {
    case NineBitCommand::reset: reset(); break;
    case NineBitCommand::read_eeprom: {
      const auto word = eeprom(*line->location);
      if (!word) return std::nullopt;
      text = std::to_string(*word);
      break;
    }
    case NineBitCommand::read_sensor: text = std::to_string(counts(now)); break;
    case NineBitCommand::read_temperature: text = std::to_string(temperature()); break;
    case NineBitCommand::write_eeprom:
      if (!write(*line->location, *line->value, Protocol::nine_bit)) return std::nullopt;
      break;
    case NineBitCommand::firmware: text = options_.firmware; break;
  }
  return with_garbage(nine_bit_reply_line(text));
}

std::optional<std::vector<std::uint8_t>> SimulatedDyna::respond_ascii(const AsciiFrame& request,
                                                                      SimTime now) {
  if (request.address != address_) return std::nullopt;
  const auto data_bytes = request_data_bytes(request.command);
  const auto command = static_cast<AsciiCommand>(request.command);
  if (!data_bytes || request.data.size() != *data_bytes || !accept_request(command)) {
    return std::nullopt;
  }
  AsciiFrame reply = make_ascii_ack(request.address, command);
  switch (command) {
    case AsciiCommand::reset: reset(); break;
    case AsciiCommand::read_sensor:
      reply = make_ascii_word_reply(request.address, command,
                                    static_cast<std::uint16_t>(counts(now)));
      break;
    case AsciiCommand::read_temperature:
      reply = make_ascii_word_reply(request.address, command,
                                    static_cast<std::uint16_t>(temperature()));
      break;
    case AsciiCommand::write_eeprom:
      if (!write(*word_at(request, 0), *word_at(request, 1), Protocol::modbus_ascii)) {
        return std::nullopt;
      }
      break;
    case AsciiCommand::read_eeprom: {
      const auto word = eeprom(*word_at(request, 0));
      if (!word) return std::nullopt;
      reply = make_ascii_word_reply(request.address, command, *word);
      break;
    }
    case AsciiCommand::revision:
      reply = make_ascii_word_reply(request.address, command, options_.revision);
      break;
  }
  std::vector<std::uint8_t> bytes = encode(reply);
  if (faults_.corrupt_lrc > 0) {
    --faults_.corrupt_lrc;
    std::uint8_t& digit = bytes[bytes.size() - 3];  // the LRC's last digit, before CR LF
    digit = digit == '0' ? '1' : '0';
  }
  return with_garbage(std::move(bytes));
}

void SimulatedDyna::reset() {
  address_ = static_cast<std::uint8_t>(eeprom_[eeprom::kModuleAddress / 2]);
  baud_code_ = eeprom_[eeprom::kBaudCode / 2];
  ++resets_;
}

std::int16_t SimulatedDyna::counts(SimTime now) const {
  const double phase = 2.0 * std::numbers::pi * now.count() / options_.sway_period_s;
  const double raw = options_.counts + options_.sway_amplitude * std::sin(phase);
  const auto offset = static_cast<std::int16_t>(eeprom_[eeprom::kSensorOffset / 2]);
  return clamp_to_word(raw - offset);
}

std::int16_t SimulatedDyna::temperature() const {
  const auto offset = static_cast<std::int16_t>(eeprom_[eeprom::kTemperatureOffset / 2]);
  return clamp_to_word(static_cast<double>(options_.temperature) - offset);
}

void SimulatedDyna::set_counts(std::int16_t counts) {
  options_.counts = counts;
  options_.sway_amplitude = 0.0;
}

void SimulatedDyna::set_serial(std::uint16_t serial) {
  options_.serial = serial;
  eeprom_[eeprom::kSerialNumber / 2] = serial;
}

void SimulatedDyna::set_motion(double amplitude, double period_s) {
  options_.sway_amplitude = amplitude;
  options_.sway_period_s = period_s;
}

void SimulatedDyna::set_temperature(std::int16_t raw) { options_.temperature = raw; }

std::optional<std::uint16_t> SimulatedDyna::eeprom(std::int64_t location) const {
  if (location < 0 || location % 2 != 0 || location / 2 >= static_cast<std::int64_t>(kWords)) {
    return std::nullopt;
  }
  return eeprom_[static_cast<std::size_t>(location / 2)];
}

bool SimulatedDyna::set_eeprom(std::int64_t location, std::uint16_t value) {
  if (!eeprom(location)) return false;
  eeprom_[static_cast<std::size_t>(location / 2)] = value;
  return true;
}

bool SimulatedDyna::accept_request(AsciiCommand command) {
  ++requests_handled_;
  if (faults_.silent > 0) {
    --faults_.silent;
    return false;
  }
  auto own = faults_.by_command.find(command);
  if (own != faults_.by_command.end() && own->second.silent > 0) {
    --own->second.silent;
    return false;
  }
  return true;
}

std::chrono::milliseconds SimulatedDyna::reply_delay(AsciiCommand command) const {
  auto own = faults_.by_command.find(command);
  const auto extra = own == faults_.by_command.end() ? std::chrono::milliseconds{0}
                                                     : own->second.delay;
  return faults_.reply_delay + extra;
}

AsciiCommand counterpart(NineBitCommand command) {
  switch (command) {
    case NineBitCommand::reset: return AsciiCommand::reset;
    case NineBitCommand::read_eeprom: return AsciiCommand::read_eeprom;
    case NineBitCommand::read_sensor: return AsciiCommand::read_sensor;
    case NineBitCommand::read_temperature: return AsciiCommand::read_temperature;
    case NineBitCommand::write_eeprom: return AsciiCommand::write_eeprom;
    case NineBitCommand::firmware: return AsciiCommand::revision;
  }
  return AsciiCommand::revision;
}

bool SimulatedDyna::write(std::int64_t location, std::uint16_t value, Protocol protocol) {
  if (!eeprom(location)) return false;
  if (location == eeprom::kModuleAddress &&
      (value < eeprom::min_address(protocol) || value > eeprom::max_address(protocol))) {
    return false;
  }
  if (location == eeprom::kBaudCode && !eeprom::baud_for_code(value)) return false;
  eeprom_[static_cast<std::size_t>(location / 2)] = value;
  if (location == eeprom::kModuleAddress) address_ = static_cast<std::uint8_t>(value);
  return true;
}

std::vector<std::uint8_t> SimulatedDyna::with_garbage(std::vector<std::uint8_t> bytes) {
  if (faults_.garbage > 0) {
    --faults_.garbage;
    bytes.insert(bytes.begin(), faults_.garbage_bytes.begin(), faults_.garbage_bytes.end());
  }
  return bytes;
}

}  // namespace tiltgate::spectron
