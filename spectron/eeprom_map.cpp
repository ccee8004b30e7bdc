#include "spectron/eeprom_map.h"

#include <array>

namespace tiltgate::spectron::eeprom {
namespace {

struct BaudCode {
  int code;
  std::uint32_t baud;
};
// "22 baud rate".
constexpr std::array<BaudCode, 5> kBaudCodes{
    {{7, 38400}, {10, 28800}, {15, 19200}, {32, 9600}, {64, 4800}}};

std::string named(std::int64_t location) {
  std::string text = "location " + std::to_string(location);
  if (const char* name = location_name(location)) text += std::string(" (") + name + ")";
  return text;
}

}  // namespace

const char* location_name(std::int64_t location) {
  switch (location) {
    case kSerialNumber: return "serial number";
    case kSensorOffset: return "sensor offset";
    case kTemperatureOffset: return "temperature sensor offset";
    case kModuleAddress: return "module address";
    case kPwmOffset: return "PWM output offset";
    case kBaudCode: return "baud rate code";
    case 2:
    case 8:
    case 12:
    case 14:
    case 18: return "reserved";
    default: break;
  }
  if (location >= kReservedFirst && location <= kReservedLast && location % 2 == 0) {
    return "reserved";
  }
  return nullptr;
}

bool is_documented(std::int64_t location) { return location_name(location) != nullptr; }

bool writable(std::int64_t location, ReservedWrites reserved) {
  switch (location) {
    case kSensorOffset:
    case kTemperatureOffset:
    case kModuleAddress:
    case kPwmOffset:
    case kBaudCode: return true;
    default: break;
  }
  // The application note's own example writes 355 to location 100 (":0268006401639C").
  return reserved == ReservedWrites::allowed && location >= kReservedFirst &&
         location <= kReservedLast && location % 2 == 0;
}

Expected<Done, std::string> check_location(std::int64_t location) {
  if (location % 2 != 0) {
    return Unexpected{"EEPROM location " + std::to_string(location) +
                      " is odd; locations are even"};
  }
  if (!is_documented(location)) {
    return Unexpected{"EEPROM location " + std::to_string(location) +
                      " is not in the memory map (2..22, 100..280)"};
  }
  return Done{};
}

Expected<Done, std::string> check_value(std::int64_t location, std::int64_t value,
                                        Protocol protocol, ReservedWrites reserved) {
  if (auto known = check_location(location); !known) return known;
  if (!writable(location, reserved)) return Unexpected{named(location) + " is read-only"};
  const std::string what = "value " + std::to_string(value) + " for " + named(location);
  if (location == kModuleAddress) {
    if (value < min_address(protocol) || value > max_address(protocol)) {
      return Unexpected{what + " is out of range " + std::to_string(min_address(protocol)) +
                        ".." + std::to_string(max_address(protocol)) + " on a " +
                        protocol_name(protocol) + " bus"};
    }
    return Done{};
  }
  if (location == kBaudCode) {
    if (!baud_for_code(value)) return Unexpected{what + " is not one of 7, 10, 15, 32, 64"};
    return Done{};
  }
  if (value < 0 || value > kMaxValue) return Unexpected{what + " is out of range 0..65535"};
  return Done{};
}

int min_address(Protocol protocol) {
  return protocol == Protocol::modbus_ascii ? kMinModbusAddress : 0;
}

int max_address(Protocol protocol) {
  return protocol == Protocol::modbus_ascii ? kMaxModbusAddress : kMaxNineBitAddress;
}

std::optional<std::uint32_t> baud_for_code(std::int64_t code) {
  for (const auto& entry : kBaudCodes) {
    if (entry.code == code) return entry.baud;
  }
  return std::nullopt;
}

std::optional<int> code_for_baud(std::uint32_t baud) {
  for (const auto& entry : kBaudCodes) {
    if (entry.baud == baud) return entry.code;
  }
  return std::nullopt;
}

}  // namespace tiltgate::spectron::eeprom
