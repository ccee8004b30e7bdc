#include "status/angle_history.h"

#include <cmath>
#include <limits>

namespace tiltgate {

namespace {

constexpr float kMissing = std::numeric_limits<float>::quiet_NaN();

std::optional<float> present(float value) {
  if (std::isnan(value)) return std::nullopt;
  return value;
}

}  // namespace

AngleRing::AngleRing(std::size_t capacity, bool temperatures)
    : slots_(capacity), temperatures_(temperatures ? capacity : 0) {}

void AngleRing::push(const AngleSample& sample) {
  if (slots_.empty()) return;
  slots_[next_] = Slot{sample.unix_ms, sample.x.value_or(kMissing), sample.y.value_or(kMissing)};
  if (!temperatures_.empty()) temperatures_[next_] = sample.temperature.value_or(kMissing);
  next_ = (next_ + 1) % slots_.size();
  if (size_ < slots_.size()) ++size_;
}

std::vector<AngleSample> AngleRing::samples() const {
  std::vector<AngleSample> out;
  out.reserve(size_);
  // The oldest sample is `size_` slots behind the next free one.
  const std::size_t first = (next_ + slots_.size() - size_) % (slots_.empty() ? 1 : slots_.size());
  for (std::size_t i = 0; i < size_; ++i) {
    const std::size_t at = (first + i) % slots_.size();
    const Slot& slot = slots_[at];
    out.push_back(AngleSample{slot.unix_ms, present(slot.x), present(slot.y),
                              temperatures_.empty() ? std::nullopt : present(temperatures_[at])});
  }
  return out;
}

}  // namespace tiltgate
