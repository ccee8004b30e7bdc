#include "mapping/sensor_view.h"

#include <algorithm>

namespace tiltgate {

bool SensorView::stale() const {
  return !state.reading || now - state.reading->taken > stale_after;
}

std::uint16_t SensorView::age_ms() const {
  if (!state.reading) return 65535;
  const auto age =
      std::chrono::duration_cast<std::chrono::milliseconds>(now - state.reading->taken).count();
  return std::uint16_t(std::clamp<long long>(age, 0, 65535));
}

std::uint16_t SensorView::alarms() const {
  return derived != nullptr && derived->valid ? derived->alarms : 0;
}

std::uint16_t SensorView::status() const {
  std::uint16_t bits = 0;
  if (online()) bits |= status_bit::online;
  if (stale()) bits |= status_bit::stale;
  if (state.last_write_failed) bits |= status_bit::last_write_failed;
  if (!state.identity_known) bits |= status_bit::identity_unknown;
  if (alarms() != 0) bits |= status_bit::alarm_active;
  if (state.answers_late) bits |= status_bit::answers_late;
  if (state.wrong_device) bits |= status_bit::wrong_device;
  if (state.standby) bits |= status_bit::standby;
  if (const DerivedState* d = valid_derived(); d != nullptr && !d->clock_synchronised)
    bits |= status_bit::clock_unsynchronised;
  return bits;
}

}  // namespace tiltgate
