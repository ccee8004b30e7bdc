// The Dyna driver's EEPROM read-back: what the module holds, published in
// SensorState::settings for the holding registers to show.
#include <spdlog/spdlog.h>

#include "spectron/dyna_driver.h"
#include "spectron/dyna_settings.h"

namespace tiltgate::spectron {

namespace asio = boost::asio;

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
  auto reply = co_await exchange(line, {DynaRequest::Kind::read_eeprom, location});
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

}  // namespace tiltgate::spectron
