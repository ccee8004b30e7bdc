// One sensor's input and holding registers rendered once from a view, so that a Modbus read
// copies a slice instead of finding and converting its points one by one
// (docs/performance.md, "The Modbus read path"). A read answers exactly what read_registers()
// answers for the same view: the same words, the same exceptions.
//
// What a rendering holds stays true for one snapshot of the sensor as long as the view's
// online and stale flags and word order are the ones it was rendered with: read() renders
// again when they changed, and clear() forgets it for a new snapshot. Points that change by
// the millisecond (age_ms) are encoded at each read.
//
// Pure: no I/O, no clock of its own. Used by one thread (a connection's reader).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "driver/expected.h"
#include "mapping/map_access.h"

namespace tiltgate {

class RegisterImage {
 public:
  // A new snapshot: the next read renders again.
  void clear() { rendered_ = false; }
  // As read_registers(map, view, table, address, words); `map` is the one every read of this
  // image passes (the sensor's).
  Expected<Done, MapFault> read(const RegisterMap& map, const SensorView& view,
                                RegisterTable table, std::uint16_t address,
                                std::span<std::uint16_t> words);

 private:
  // One table's registers from `first` on, with what each register is (the k* bits).
  struct Table {
    std::uint32_t first = 0;
    std::vector<std::uint16_t> words;
    std::vector<std::uint8_t> kinds;
  };

  void render(const RegisterMap& map, const SensorView& view);
  void render_table(const RegisterMap& map, const SensorView& view, RegisterTable table);

  std::array<Table, 2> tables_;  // input, holding
  std::vector<const Point*> live_;  // read again at every read: age_ms
  bool rendered_ = false;
  // A map validate() refuses (points that overlap): every read goes to read_registers().
  bool overlapping_ = false;
  // The view's state rendered.
  bool online_ = false;
  bool stale_ = false;
  WordOrder order_ = WordOrder::big;
};

}  // namespace tiltgate
