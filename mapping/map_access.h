// Modbus reads and writes evaluated against a register map and one sensor's cached state.
// Pure: no I/O, no clock of its own (the caller passes "now").
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include "config/config.h"
#include "driver/expected.h"
#include "driver/sensor_state.h"
#include "mapping/register_map.h"

namespace tiltgate {

// Why a request cannot be answered from the map; the values are the Modbus exception codes.
enum class MapFault : std::uint8_t {
  no_such_table = 0x01,     // the map has nothing in that table: illegal function
  illegal_address = 0x02,  // unmapped register, or a request that splits a multi-word value
  illegal_value = 0x03,     // a written value outside the point's range
  unavailable = 0x0B,       // measurement asked of an offline or stale sensor
};

struct SensorView {
  const SensorState& state;
  SteadyClock::time_point now;
  std::chrono::milliseconds stale_after;
  std::span<const std::uint16_t> written;  // holding shadow: last values written, 0 before
  WordOrder order = WordOrder::big;

  bool stale() const;
  std::uint16_t age_ms() const;  // 65535 when there never was a reading
  std::uint16_t status() const;
};

namespace status_bit {
constexpr std::uint16_t online = 1 << 0;
constexpr std::uint16_t stale = 1 << 1;
constexpr std::uint16_t last_write_failed = 1 << 2;
constexpr std::uint16_t identity_unknown = 1 << 3;
}  // namespace status_bit

Expected<std::vector<std::uint16_t>, MapFault> read_registers(const RegisterMap& map,
                                                              const SensorView& sensor,
                                                              RegisterTable table,
                                                              std::uint16_t address,
                                                              std::uint16_t count);

Expected<std::vector<bool>, MapFault> read_bits(const RegisterMap& map, const SensorView& sensor,
                                                RegisterTable table, std::uint16_t address,
                                                std::uint16_t count);

struct PlannedWrite {
  const Point* point;
  double value;                      // decoded, range-checked
  std::vector<std::uint16_t> words;  // as received, for the holding shadow
};

// Checks a write of holding registers: every register must belong to a writable point that
// the request covers whole, and every value must be in its point's range.
Expected<std::vector<PlannedWrite>, MapFault> plan_register_write(
    const RegisterMap& map, WordOrder order, std::uint16_t address,
    std::span<const std::uint16_t> words);

}  // namespace tiltgate
