// A model of one Rieker Flex sensor on the bus, answering requests as the manual describes.
// Pure: time is passed in (seconds since the simulation started), so tests are deterministic.
//
// Choices where the manual is silent (documented here and tested):
// - The checks run in this order: unknown function (NAK 1), lock level for a function that
//   changes the sensor (NAK 4), then DL and data (NAK 3), then the model (NAK 2).
// - Get Angle: an H6 is dual axis and answers types 2, 3, 4; type 1 (single axis) gets NAK 2.
//   An H4360 is single axis and answers type 1; types 2, 3, 4 get NAK 2. Set Zero To Value on
//   axis 2 (Y) of an H4360 also gets NAK 2.
// - ACK and NAK frames sent to a sensor are "not a query": no reply.
// - Set Address answers the ACK from the old address, then moves (the manual's example).
// - Restart: ACK first; then the lock level returns to 0, temporary zero offsets are lost and a
//   pending baud code becomes the active one.
// - Zero offsets: Set Zero To Value and a permanent Set Zero To Angle replace an axis's
//   permanent offset and drop its temporary one; a temporary Set Zero To Angle takes precedence
//   until restart. Offsets are subtracted from the raw angle.
// - Broadcast (0xFFFC) requests are answered like addressed ones, from the sensor's address.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rieker/codec.h"

namespace tiltgate::rieker {


using SimTime = std::chrono::duration<double>;  // seconds since the simulation started

struct SimulatedSensorOptions {
  Model model = Model::h6;
  std::uint16_t address = kFactoryAddress;
  std::string serial = "962285";     // space padded to 10 bytes on the wire
  std::string firmware = "Rev A.8";  // 7 bytes on the wire
  // Raw angles in degrees: base + amplitude * sin(2 pi t / period) on X, cos on Y. Zero
  // amplitude keeps them fixed.
  double angle_x = 0.0;
  double angle_y = 0.0;
  double sway_amplitude = 0.0;
  double sway_period_s = 20.0;
  int filter = kDefaultFilter;
  int baud_code = kDefaultBaudCode;
};

// Faults of one function only, so a test can make exactly Set Filter fail. silent and nak
// count queries of that function addressed to this sensor.
struct FunctionFaults {
  int silent = 0;  // answer nothing
  int nak = 0;     // answer NAK nak_code instead (the query has no effect)
  NakCode nak_code = NakCode::data_invalid;
  // Answer every query of this function this much later (on top of SensorFaults::reply_delay).
  std::chrono::milliseconds delay{0};
};

// Faults a test can inject. silent and busy count queries addressed to this sensor;
// corrupt_crc and garbage count replies. The whole-sensor faults apply before by_function's.
struct SensorFaults {
  int silent = 0;       // answer nothing
  int busy = 0;         // answer NAK 5
  int corrupt_crc = 0;  // flip the low byte of the reply's CRC
  int garbage = 0;      // send garbage_bytes before the reply
  // Looks like a header claiming DL 200, so a parser that trusts the first header waits for
  // 209 bytes that never come.
  std::vector<std::uint8_t> garbage_bytes = {0x00, 0x00, 0x00, 0xDF, 0x00, 0x05, 0xC8};
  // Answer everything this much later: a slow sensor, or a slow adapter in between.
  std::chrono::milliseconds reply_delay{0};
  std::map<Function, FunctionFaults> by_function;
};

class SimulatedSensor {
 public:
  explicit SimulatedSensor(SimulatedSensorOptions options);

  // The reply the sensor sends to `request` (nullopt: silence), with the silent and busy
  // faults applied.
  std::optional<Frame> handle(const Frame& request, SimTime now);
  // handle(), encoded for the wire, with the byte-level faults (CRC, garbage) applied.
  std::optional<std::vector<std::uint8_t>> respond(const Frame& request, SimTime now);
  // A frame that arrived with a bad CRC (header and data as received): NAK 0 when it is
  // addressed to this sensor, silence otherwise.
  std::optional<Frame> handle_crc_failure(const Frame& damaged);

  // Power cycle: what Restart does, without a request.
  void restart();

  // The angles a Get Angle would report at `now`, zero offsets subtracted.
  double angle_x(SimTime now) const;
  double angle_y(SimTime now) const;
  void set_angles(double x, double y);  // fixed raw angles from now on
  void set_motion(double amplitude, double period_s);
  // Another sensor put in its place: it reports this serial from now on.
  void set_serial(std::string serial) { options_.serial = std::move(serial); }

  SensorFaults& faults() { return faults_; }
  // How much later than usual this sensor answers a query of `function` (the simulator waits).
  std::chrono::milliseconds reply_delay(std::uint16_t function) const;

  Model model() const { return options_.model; }
  std::uint16_t address() const { return address_; }
  const std::string& serial() const { return options_.serial; }
  const std::string& firmware() const { return options_.firmware; }
  LockLevel lock_level() const { return lock_; }
  int filter() const { return filter_; }
  int baud_code() const { return baud_code_; }
  std::optional<int> pending_baud_code() const { return pending_baud_code_; }
  double zero_offset(Axis axis) const;  // the offset in effect (temporary, else permanent)
  std::uint64_t requests_handled() const { return requests_handled_; }
  // Queries of `function` addressed to this sensor, answered or not.
  std::uint64_t requests_of(Function function) const;
  std::uint64_t restarts() const { return restarts_; }

 private:
  bool addressed(std::uint16_t dest) const;
  double raw_angle(Axis axis, SimTime now) const;
  // The reply to a request addressed to this sensor, faults aside.
  std::optional<Frame> answer(const Frame& request, SimTime now);
  Frame answer_get_angle(const Frame& request, SimTime now) const;
  Frame answer_change_lock(const Frame& request);
  Frame answer_set_zero_to_value(const Frame& request);
  Frame answer_set_zero_to_angle(const Frame& request, SimTime now);
  Frame answer_setting(const Frame& request);  // set address, baud, filter
  Frame ack(const Frame& request) const;
  Frame nak(const Frame& request, NakCode code) const;

  SimulatedSensorOptions options_;
  std::uint16_t address_;
  LockLevel lock_ = LockLevel::locked;  // "Protection Levels": 0 after power-up or restart
  int filter_;
  int baud_code_;
  std::optional<int> pending_baud_code_;
  double permanent_zero_[2] = {0.0, 0.0};
  std::optional<double> temporary_zero_[2];
  SensorFaults faults_;
  std::uint64_t requests_handled_ = 0;
  std::map<std::uint16_t, std::uint64_t> requests_by_function_;
  std::uint64_t restarts_ = 0;
};

}  // namespace tiltgate::rieker
