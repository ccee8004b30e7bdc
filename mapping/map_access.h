// Modbus reads and writes evaluated against a register map and one sensor's cached state.
// Pure: no I/O, no clock of its own (the caller passes "now").
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "driver/expected.h"
#include "mapping/register_map.h"
#include "mapping/sensor_view.h"

namespace tiltgate {

// Why a request cannot be answered from the map; the values are the Modbus exception codes.
enum class MapFault : std::uint8_t {
  no_such_table = 0x01,    // the map has nothing in that table: illegal function
  illegal_address = 0x02,  // unmapped register, or a request that splits a multi-word value
  illegal_value = 0x03,    // a written value outside the point's range
  unavailable = 0x0B,      // measurement asked of an offline or stale sensor
};

// A measurement of an offline or stale sensor reads as the view's OfflineRead says:
// exception: unavailable; last_value: the last reading (unavailable if there never was one);
// substitute: numeric points show view.substitute as is (no scale), bit points 0.
// The registers [address, address + words.size()) into `words`: the Modbus read path, which
// allocates nothing (a connection hands in its own buffer).
Expected<Done, MapFault> read_registers(const RegisterMap& map, const SensorView& sensor,
                                        RegisterTable table, std::uint16_t address,
                                        std::span<std::uint16_t> words);
// One point of `map`'s registers into `words` (its words() long), as read_registers() reads
// them in any range that holds the point whole: what mapping/register_image.h renders from.
Expected<Done, MapFault> read_point(const Point& point, const SensorView& sensor,
                                    std::span<std::uint16_t> words);
// The same into a new vector of `count`.
Expected<std::vector<std::uint16_t>, MapFault> read_registers(const RegisterMap& map,
                                                              const SensorView& sensor,
                                                              RegisterTable table,
                                                              std::uint16_t address,
                                                              std::uint16_t count);

// The bits into `bits` (resized to `count`; its capacity kept), and into a new vector.
Expected<Done, MapFault> read_bits(const RegisterMap& map, const SensorView& sensor,
                                   RegisterTable table, std::uint16_t address,
                                   std::uint16_t count, std::vector<bool>& bits);
Expected<std::vector<bool>, MapFault> read_bits(const RegisterMap& map, const SensorView& sensor,
                                                RegisterTable table, std::uint16_t address,
                                                std::uint16_t count);

struct PlannedWrite {
  const Point* point;
  double value;                      // decoded, unscaled, range-checked
  std::vector<std::uint16_t> words;  // as received, for the holding shadow
};

// Checks a write of holding registers: every register must belong to a writable point that
// the request covers whole, every float must be a number (not NaN, infinite or subnormal, the
// mark of swapped words), and every value must be in its point's range. `order` is the
// [server] word order, for points without one of their own.
Expected<std::vector<PlannedWrite>, MapFault> plan_register_write(
    const RegisterMap& map, WordOrder order, std::uint16_t address,
    std::span<const std::uint16_t> words);

// The same write for one writable holding point of `map` given its value (before scaling), as
// a Sparkplug DCMD asks for a setting: the value's range is checked, then it is encoded as
// the point's registers and planned like a Modbus write of them, with the same checks.
Expected<std::vector<PlannedWrite>, MapFault> plan_point_write(const RegisterMap& map,
                                                               WordOrder order, const Point& point,
                                                               double value);

}  // namespace tiltgate
