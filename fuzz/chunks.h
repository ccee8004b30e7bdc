// Cuts a fuzz input into the random-sized pieces a serial or TCP read returns: the first byte
// seeds the piece sizes (1..64 bytes), the rest is the byte stream. So one input exercises a
// stream parser's resumption at every boundary libFuzzer cares to try.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>

namespace tiltgate::fuzz {

// Stops the run as a crash: the invariant a harness checks does not hold.
[[noreturn]] inline void invariant_broken() { __builtin_trap(); }

inline void check(bool holds) {
  if (!holds) invariant_broken();
}

class Chunks {
 public:
  explicit Chunks(std::span<const std::uint8_t> input)
      : state_(input.empty() ? 1u : input[0] * 2654435761u + 1u),
        rest_(input.empty() ? input : input.subspan(1)) {}

  std::span<const std::uint8_t> stream() const { return rest_; }
  bool done() const { return offset_ >= rest_.size(); }

  // The next piece, at most `limit` bytes (and at least 1 while !done()).
  std::span<const std::uint8_t> next(std::size_t limit = SIZE_MAX) {
    state_ ^= state_ << 13;
    state_ ^= state_ >> 17;
    state_ ^= state_ << 5;
    std::size_t size = std::min<std::size_t>({1 + state_ % 64, limit, rest_.size() - offset_});
    auto piece = rest_.subspan(offset_, size);
    offset_ += size;
    return piece;
  }

 private:
  std::uint32_t state_;
  std::span<const std::uint8_t> rest_;
  std::size_t offset_ = 0;
};

}  // namespace tiltgate::fuzz
