#include "spectron/dyna_driver.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <utility>

#include "driver/visible_text.h"
#include "spectron/eeprom_map.h"

namespace tiltgate::spectron {

namespace asio = boost::asio;

namespace {

using Kind = DynaRequest::Kind;

// The settings that are one EEPROM word each ("Memory Map", spectron/eeprom_map.h), read back
// with the identity.
constexpr std::array<WriteTarget, 5> kEepromSettings{
    setting::sensor_offset, setting::temperature_offset, setting::pwm_offset,
    WriteTarget::baud_code, WriteTarget::bus_address};

// The EEPROM location behind a named setting; none for the window and the command.
constexpr std::optional<std::uint16_t> location_of(WriteTarget target) {
  switch (target) {
    case setting::sensor_offset: return eeprom::kSensorOffset;
    case setting::temperature_offset: return eeprom::kTemperatureOffset;
    case setting::pwm_offset: return eeprom::kPwmOffset;
    case WriteTarget::bus_address: return eeprom::kModuleAddress;
    case WriteTarget::baud_code: return eeprom::kBaudCode;
    default: return std::nullopt;
  }
}

// Far beyond any value a setting takes, so the conversion to an integer below is exact.
constexpr double kLargestChecked = 1e9;

bool is_whole(double value) {
  return std::isfinite(value) && value == std::floor(value) && std::fabs(value) <= kLargestChecked;
}

WriteResult bad_value(std::string detail) {
  return Unexpected{WriteError{WriteErrorKind::bad_value, std::move(detail)}};
}

// The only command: the "0" / 0x65 reset of the processor.
constexpr double kResetCommand = 1;

}  // namespace

WriteError to_write_error(const ExchangeError& error, std::string_view step) {
  const std::string detail = fmt::format("{}: {}", step, error.detail);
  // The Dyna has no NAKs: a reply that is not the acknowledgement is all it can refuse with.
  switch (error.kind) {
    case ExchangeError::Kind::line: return {WriteErrorKind::no_response, detail};
    case ExchangeError::Kind::bad_request: return {WriteErrorKind::bad_value, detail};
    case ExchangeError::Kind::bad_reply: break;
  }
  return {WriteErrorKind::refused, detail};
}

DynaDriver::DynaDriver(DynaDriverOptions options)
    : PolledSensorDriver(options.reply_timeouts), options_(std::move(options)) {
  state_.bus_address = std::uint32_t(options_.address);
}

asio::awaitable<Expected<DynaAnswer, ExchangeError>> DynaDriver::exchange(
    Line& line, DynaRequest request, ExchangeOptions options, std::optional<int> address) {
  auto transaction =
      DynaTransaction::make(options_.protocol, address.value_or(options_.address), request);
  if (!transaction) {
    co_return Unexpected{
        ExchangeError{ExchangeError::Kind::bad_request, LineError::timeout, transaction.error()}};
  }
  auto sent = co_await transact_counted(line, transaction->line_request(), options);
  state_.counters.checksum_errors += std::uint32_t(transaction->checksum_errors());
  if (!sent) {
    co_return Unexpected{ExchangeError{ExchangeError::Kind::line, sent.error(),
                                       fmt::format("{}: {}", request_name(request.kind),
                                                   to_string(sent.error()))}};
  }
  auto answer = transaction->answer();
  if (!answer) {
    co_return Unexpected{ExchangeError{ExchangeError::Kind::bad_reply, LineError::timeout,
                                       fmt::format("{}: {}", request_name(request.kind),
                                                   describe(answer.error()))}};
  }
  co_return std::move(*answer);
}

asio::awaitable<bool> DynaDriver::read_identity(Line& line) {
  const auto generation = line.generation();
  auto firmware = co_await exchange(line, {Kind::firmware});
  if (!firmware && firmware.error().kind == ExchangeError::Kind::line) co_return false;
  auto serial = co_await exchange(line, {Kind::read_eeprom, eeprom::kSerialNumber});
  if (!serial && serial.error().kind == ExchangeError::Kind::line) co_return false;

  // A module that answers identity requests with nonsense still measures: carry on without it
  // rather than asking again every poll (status bit 3 stays set until the next reconnect).
  // The settings are read next (PolledSensorDriver::poll()).
  identity_read_on(generation);
  if (firmware) state_.firmware = firmware->text;
  if (serial) state_.serial = std::to_string(serial->number);  // EEPROM 4, a decimal number
  state_.identity_known = firmware.has_value() && serial.has_value();
  if (state_.identity_known) {
    if (!rechecking_wrong_device())
      spdlog::info("{}: Dyna at {} is serial '{}', firmware '{}'", options_.name, options_.address,
                   visible_text(state_.serial), visible_text(state_.firmware));
  } else {
    spdlog::warn("{}: could not read the identity of the Dyna at {}: {}", options_.name,
                 options_.address, firmware ? serial.error().detail : firmware.error().detail);
  }
  co_return true;
}

asio::awaitable<void> DynaDriver::read_measurement(Line& line) {
  // Both values make one reading, so a Modbus read never mixes two polls.
  auto counts = co_await exchange(line, {Kind::read_sensor});
  if (!counts) {
    failed_measurement(counts.error());
    co_return;
  }
  auto temperature = co_await exchange(line, {Kind::read_temperature});
  if (!temperature) {
    failed_measurement(temperature.error());
    co_return;
  }
  Reading reading;
  reading.raw_counts = counts->number;
  reading.raw_temperature = temperature->number;
  reading.temperature_c = (temperature->number - options_.temperature_zero_counts) /
                          options_.temperature_counts_per_degree;
  reading.angle_x = (counts->number - options_.zero_counts) / options_.counts_per_degree;
  reading.angle_y = NAN;  // single axis
  reading.taken = reply_time(line.last_timing());
  state_.reading = reading;
  ++state_.sample_seq;
  ++state_.counters.polls_ok;
}

void DynaDriver::failed_measurement(const ExchangeError& error) {
  ++state_.counters.polls_failed;
  if (error.kind != ExchangeError::Kind::line) {
    spdlog::debug("{}: unusable reply: {}", options_.name, error.detail);
  }
}

// EEPROM read-back: what the module holds, published in SensorState::settings for the holding
// registers to show.

asio::awaitable<bool> DynaDriver::read_settings(Line& line) {
  for (WriteTarget target : kEepromSettings) {
    auto read = co_await read_back(line, *location_of(target));
    if (!read && read.error().kind == ExchangeError::Kind::line) co_return false;
  }
  if (const auto location = eeprom_location()) {
    auto read = co_await read_back(line, *location);
    if (!read && read.error().kind == ExchangeError::Kind::line) co_return false;
  }
  co_return true;
}

asio::awaitable<Expected<std::uint16_t, ExchangeError>> DynaDriver::read_back(
    Line& line, std::uint16_t location) {
  auto reply = co_await exchange(line, {Kind::read_eeprom, location});
  if (!reply) {
    spdlog::debug("{}: could not read EEPROM {} back: {}", options_.name, location,
                  reply.error().detail);
    publish(location, std::nullopt);
    co_return Unexpected{reply.error()};
  }
  // A word on the wire: 9-bit replies are decimal text, Modbus-ASCII ones 4 hex digits.
  const auto word = std::uint16_t(reply->number);
  publish(location, word);
  co_return word;
}

void DynaDriver::publish(std::uint16_t location, std::optional<std::uint16_t> value) {
  KnownSettings& settings = state_.settings;
  const auto set = [&](WriteTarget target) {
    if (value)
      settings.set(target, *value);
    else
      settings.forget(target);
  };
  for (WriteTarget target : kEepromSettings)
    if (location_of(target) == location) set(target);
  if (eeprom_location() == location) set(setting::eeprom_value);
}

std::optional<std::uint16_t> DynaDriver::eeprom_location() const {
  const auto selected = state_.settings.get(setting::eeprom_location);
  if (!selected) return std::nullopt;
  return std::uint16_t(*selected);
}

// Writes: checks against the memory map, the EEPROM writes with their read-back, the EEPROM
// window, the module address and the reset.

WriteResult DynaDriver::check_location_value(std::int64_t location, double value) const {
  if (!is_whole(value)) return bad_value(fmt::format("{} is not a whole number", value));
  const auto reserved = options_.reserved_writes ? eeprom::ReservedWrites::allowed
                                                 : eeprom::ReservedWrites::refused;
  auto allowed = eeprom::check_value(location, std::int64_t(value), options_.protocol, reserved);
  if (!allowed) return bad_value(allowed.error());
  return Done{};
}

WriteResult DynaDriver::check_window_value(std::optional<std::uint16_t> location,
                                           double value) const {
  if (!location) return bad_value("no EEPROM location selected");
  return check_location_value(*location, value);
}

WriteResult DynaDriver::check_write(WriteTarget target, double value) const {
  if (const auto location = location_of(target)) return check_location_value(*location, value);
  switch (target) {
    case WriteTarget::command:
      if (value != kResetCommand) return bad_value("command must be 1 (reset)");
      return Done{};
    case setting::eeprom_location: {
      if (!is_whole(value)) return bad_value(fmt::format("{} is not a whole number", value));
      auto known = eeprom::check_location(std::int64_t(value));
      if (!known) return bad_value(known.error());
      return Done{};
    }
    case setting::eeprom_value: return check_window_value(eeprom_location(), value);
    default:
      return Unexpected{WriteError{WriteErrorKind::not_supported, "not a Dyna setting"}};
  }
}

WriteResult DynaDriver::check_writes(std::span<const SettingWrite> writes) const {
  // Location and value written in one request: the value goes to the new location, so it is
  // checked against that one, before the location is selected.
  std::optional<std::uint16_t> location = eeprom_location();
  for (const SettingWrite& w : writes) {
    auto checked = w.target == setting::eeprom_value ? check_window_value(location, w.value)
                                                         : check_write(w.target, w.value);
    if (!checked) return checked;
    if (w.target == setting::eeprom_location) location = std::uint16_t(w.value);
  }
  return Done{};
}

std::optional<std::uint32_t> DynaDriver::address_after(WriteTarget target, double value) const {
  if (target == setting::eeprom_value && eeprom_location() == eeprom::kModuleAddress) {
    target = WriteTarget::bus_address;
  }
  return SensorDriver::address_after(target, value);
}

void DynaDriver::abandon(std::span<const SettingWrite> done) {
  const bool selected = std::any_of(done.begin(), done.end(), [](const SettingWrite& w) {
    return w.target == setting::eeprom_location;
  });
  if (!selected) return;
  // The request's value was refused: its location selection goes with it.
  KnownSettings& settings = state_.settings;
  for (auto [target, before] : {std::pair(setting::eeprom_location, selection_before_.location),
                                std::pair(setting::eeprom_value, selection_before_.value)}) {
    if (before)
      settings.set(target, *before);
    else
      settings.forget(target);
  }
}

asio::awaitable<WriteResult> DynaDriver::write(Line& line, WriteTarget target, double value) {
  auto checked = check_write(target, value);
  if (!checked) co_return checked;
  WriteResult result = Done{};
  switch (target) {
    case setting::eeprom_location:
      result = co_await select_location(line, std::uint16_t(value));
      break;
    case setting::eeprom_value:
      result = co_await write_location(line, *eeprom_location(), std::uint16_t(value));
      break;
    case WriteTarget::command: result = co_await reset(line); break;
    default: result = co_await write_location(line, *location_of(target), std::uint16_t(value));
  }
  state_.last_write_failed = !result;
  co_return result;
}

asio::awaitable<WriteResult> DynaDriver::select_location(Line& line, std::uint16_t location) {
  // Read as part of the selection, so eeprom_value shows what the module holds there.
  auto reply = co_await exchange(line, {Kind::read_eeprom, location});
  if (!reply) co_return Unexpected{to_write_error(reply.error(), "read EEPROM")};
  KnownSettings& settings = state_.settings;
  selection_before_ = {settings.get(setting::eeprom_location),
                       settings.get(setting::eeprom_value)};
  settings.set(setting::eeprom_location, location);
  publish(location, std::uint16_t(reply->number));
  co_return Done{};
}

asio::awaitable<WriteResult> DynaDriver::write_location(Line& line, std::uint16_t location,
                                                        std::uint16_t value) {
  if (location == eeprom::kModuleAddress) {
    auto moved = co_await set_address(line, value);
    if (moved) co_await read_back(line, location);  // at the new address
    co_return moved;
  }
  auto reply = co_await exchange(line, {Kind::write_eeprom, location, value});
  if (!reply) co_return Unexpected{to_write_error(reply.error(), "write EEPROM")};
  // What the module holds now, not what was sent (unknown if the read goes unanswered).
  co_await read_back(line, location);
  if (location == eeprom::kBaudCode) {
    spdlog::warn("{}: Dyna {} stores baud code {} ({} baud), in force after its next reset; the "
                 "bus's baud must then be changed to match",
                 options_.name, options_.address, value, *eeprom::baud_for_code(value));
  }
  co_return Done{};
}

asio::awaitable<WriteResult> DynaDriver::set_address(Line& line, int new_address) {
  // Not retried: after a lost acknowledgement the module may already answer only at the new
  // address, so a retry would go to nobody.
  auto reply = co_await exchange(line, {Kind::write_eeprom, eeprom::kModuleAddress, new_address},
                                 ExchangeOptions{0, {}});
  if (!reply && reply.error().kind != ExchangeError::Kind::line) {
    co_return Unexpected{to_write_error(reply.error(), "set address")};
  }
  if (!reply) {
    // No acknowledgement: did the change happen anyway? Ask the new address before giving up.
    auto there = co_await exchange(line, {Kind::read_eeprom, eeprom::kModuleAddress}, {},
                                   new_address);
    if (!there || there->number != new_address) {
      co_return Unexpected{WriteError{
          WriteErrorKind::no_response,
          fmt::format("set address: no acknowledgement, and no module answers at {}", new_address)}};
    }
  }
  spdlog::info("{}: Dyna moved from address {} to {}", options_.name, options_.address,
               new_address);
  follow_address(std::uint32_t(new_address));
  co_return Done{};
}

void DynaDriver::follow_address(std::uint32_t address) {
  options_.address = int(address);
  state_.bus_address = address;
}

asio::awaitable<WriteResult> DynaDriver::reset(Line& line) {
  auto reply = co_await exchange(line, {Kind::reset}, ExchangeOptions{-1, options_.reset_settle});
  if (!reply) co_return Unexpected{to_write_error(reply.error(), "reset")};
  // A reset may bring another firmware (or module) back: read the identity again, like after a
  // reconnect.
  forget_identity();
  spdlog::info("{}: Dyna {} reset", options_.name, options_.address);
  co_return Done{};
}

}  // namespace tiltgate::spectron
