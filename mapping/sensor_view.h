// One sensor as a Modbus read sees it at one instant: its cached state, what was derived from
// its last reading, the holding shadow, and the read policies. Pure: "now" is passed in.
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <string_view>

#include "driver/sensor_state.h"
#include "mapping/derived_state.h"
#include "mapping/point_types.h"

namespace tiltgate {

struct SensorView {
  const SensorState& state;
  SteadyClock::time_point now;
  std::chrono::milliseconds stale_after;
  std::span<const std::uint16_t> written;  // holding shadow: last values written, 0 before
  WordOrder order = WordOrder::big;        // for points without a word_order of their own
  // Mounting-corrected angles, tilt and alarms; when non-null and valid, angle sources read
  // from it instead of the raw reading.
  const DerivedState* derived = nullptr;
  OfflineRead offline = OfflineRead::exception;
  double substitute = 0.0;  // offline == substitute: what numeric measurement points show
  std::uint16_t model_code = 0;  // what input register 37 shows (ModelDescriptor::model_code)

  // Online now: answering, and heard from within stale_after (driver/sensor_state.h), so the
  // online bit clears no later than the measurements turn stale.
  bool online() const { return online_at(state, now, stale_after); }
  bool stale() const;
  // The device answering is not the configured sensor (driver/sensor_state.h).
  bool wrong_device() const { return state.wrong_device; }
  // The gateway is the standby of a redundant pair: what it serves was heard on the line.
  bool standby() const { return state.standby; }
  std::uint16_t age_ms() const;  // 65535 when there never was a reading
  std::uint16_t status() const;
  std::uint16_t alarms() const;  // alarm_bit flags, 0 without derived state
  // The derived state when there is one with a reading (else none).
  const DerivedState* valid_derived() const {
    return derived != nullptr && derived->valid ? derived : nullptr;
  }
};

namespace status_bit {
constexpr std::uint16_t online = 1 << 0;
constexpr std::uint16_t stale = 1 << 1;
constexpr std::uint16_t last_write_failed = 1 << 2;
constexpr std::uint16_t identity_unknown = 1 << 3;
constexpr std::uint16_t alarm_active = 1 << 4;
constexpr std::uint16_t answers_late = 1 << 5;
// Another device than the configured sensor answers at its address ([[sensor]] serial):
// measurements read as `offline` says and writes are refused.
constexpr std::uint16_t wrong_device = 1 << 6;
// This gateway is the standby of a redundant pair (driver/sensor_state.h standby): the values
// were heard on the line, the active gateway's polls and the sensor's replies, not asked for.
constexpr std::uint16_t standby = 1 << 7;
// The last reading was taken while the system clock was not synchronised (docs/operations.md,
// "The clock"): its UTC time may be off by more than the record should trust.
constexpr std::uint16_t clock_unsynchronised = 1 << 8;
}  // namespace status_bit

}  // namespace tiltgate
