// The Dyna's EEPROM, as the application note's "Memory Map" lists it: 16-bit words at even
// locations. Which ones exist, which the gateway may write, and which values they take
// (assumption A10 in spectron/assumptions.h).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "driver/expected.h"
#include "spectron/protocol.h"

namespace tiltgate::spectron::eeprom {

inline constexpr std::uint16_t kSerialNumber = 4;
inline constexpr std::uint16_t kSensorOffset = 6;
inline constexpr std::uint16_t kTemperatureOffset = 10;
inline constexpr std::uint16_t kModuleAddress = 16;
inline constexpr std::uint16_t kPwmOffset = 20;
inline constexpr std::uint16_t kBaudCode = 22;
inline constexpr std::uint16_t kFirstListed = 2;     // "2 reserved"
inline constexpr std::uint16_t kLastListed = 22;     // "22 baud rate"
inline constexpr std::uint16_t kReservedFirst = 100;  // "100 .. 280 reserved"
inline constexpr std::uint16_t kReservedLast = 280;
inline constexpr std::uint32_t kMaxValue = 0xFFFF;    // one 16-bit word

// "Module address = 0 (factory set)" on the 9-bit bus; Modbus-ASCII: "from 1 to 250".
inline constexpr int kMaxNineBitAddress = 255;
inline constexpr int kMinModbusAddress = 1;
inline constexpr int kMaxModbusAddress = 250;

// "serial number", "reserved", ...; nullptr for a location the map does not list.
const char* location_name(std::int64_t location);
// Even, and listed (2..22) or in the reserved block 100..280.
bool is_documented(std::int64_t location);
// What the gateway may write: the named settings 6, 10, 16, 20, 22, and with
// `reserved_writes` (the sensor's eeprom_reserved_writes) the reserved block 100..280 too.
enum class ReservedWrites { refused, allowed };
bool writable(std::int64_t location, ReservedWrites reserved = ReservedWrites::refused);

// Whether `location` may be read or written at all (is_documented), with the reason if not.
Expected<Done, std::string> check_location(std::int64_t location);
// Whether `value` may be written to `location` through the gateway on a `protocol` bus; the
// error says why not ("location 4 (serial number) is read-only", "baud code 8 is not one of
// 7, 10, 15, 32, 64").
Expected<Done, std::string> check_value(std::int64_t location, std::int64_t value,
                                        Protocol protocol,
                                        ReservedWrites reserved = ReservedWrites::refused);

// Module address range of a protocol.
int min_address(Protocol protocol);
int max_address(Protocol protocol);

// Location 22 codes: 7 = 38400, 10 = 28800, 15 = 19200, 32 = 9600, 64 = 4800.
std::optional<std::uint32_t> baud_for_code(std::int64_t code);
std::optional<int> code_for_baud(std::uint32_t baud);

}  // namespace tiltgate::spectron::eeprom
