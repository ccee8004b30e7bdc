#include "modbus_rtu/timing.h"

#include <array>

namespace tiltgate::modbus_rtu {
namespace {

constexpr std::array<Named<Parity>, 3> kParities{{
    {"even", Parity::even},
    {"odd", Parity::odd},
    {"none", Parity::none},
}};

// Serial Line 2.5.1.1: "for baud rates greater than 19200 Bps, fixed values".
constexpr std::uint32_t kFixedAbove = 19200;
constexpr std::chrono::microseconds kFixedFrameGap{1750};
constexpr std::chrono::microseconds kFixedCharGap{750};

// `characters` (in tenths) character times in microseconds, rounded up.
std::chrono::microseconds characters(std::uint64_t tenths, std::uint32_t baud, unsigned bits) {
  const std::uint64_t numerator = tenths * bits * 1'000'000ull;
  const std::uint64_t denominator = 10ull * baud;
  return std::chrono::microseconds((numerator + denominator - 1) / denominator);
}

}  // namespace

std::span<const Named<Parity>> parity_names() { return kParities; }

int default_stop_bits(Parity parity) { return parity == Parity::none ? 2 : 1; }

unsigned bits_per_character(Parity parity, int stop_bits) {
  return 1 + 8 + (parity == Parity::none ? 0 : 1) + static_cast<unsigned>(stop_bits);
}

RtuTiming rtu_timing(std::uint32_t baud, unsigned bits_per_char) {
  const auto character = characters(10, baud, bits_per_char);
  if (baud > kFixedAbove) return RtuTiming{character, kFixedFrameGap, kFixedCharGap};
  return RtuTiming{character, characters(35, baud, bits_per_char),
                   characters(15, baud, bits_per_char)};
}

}  // namespace tiltgate::modbus_rtu
