// Which model a sensor is, found the way `scan` finds it: the sensor is polled through a driver
// for one model of its family after another, the model it was given first, until one gets a
// reading. A model whose measurement the sensor refuses (a dual-axis Get Angle to a single-axis
// sensor is refused) is not the sensor's. `info`, `set` and `watch` do this for every sensor
// whose model the options did not name; a model that was named (--model, or the configuration)
// still decides the driver, and the user is told when the sensor measures as another.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <string>
#include <string_view>

#include "driver/sensor_driver.h"
#include "commission/commission_bus.h"
#include "commission/commission_events.h"
#include "commission/poll_outcome.h"

namespace tiltgate {

// Polls a command gives one sensor for its identity and a reading: a driver reads the identity
// before the first measurement, and a sensor that answered only part of it gets a few more.
inline constexpr int kMaxIdentityPolls = 3;

// Polls a few times (the identity is read before the first measurement) until the sensor has
// told its identity and given a reading, stops answering, or `stopping` turns true. The
// outcome is the last poll's.
boost::asio::awaitable<PollOutcome> poll_for_identity(Line& line, SensorDriver& driver,
                                                      const bool& stopping);

struct ModelCheck {
  std::string polled_as;    // the model the sensor had before the check
  std::size_t family_models = 0;  // how many models its family has
  PollOutcome polled;       // what polling it as that model came to
  // Why that was no reading, as the sensor's driver words a refusal; empty after a reading.
  std::string polled_refusal;
  std::string measured_as;  // the model of the family that got a reading; empty: none did
  bool adopted = false;     // the sensor now has that model and its driver
  // The last poll through the sensor's driver as it is after the check.
  PollOutcome outcome() const { return adopted ? PollOutcome{PollResult::reading} : polled; }
};

// Polls `sensor` as its model; when it answers without a reading, as each other model of its
// family in turn. A sensor whose model was detected (ModelSource::detected) takes the model
// that measured, with that model's driver, which has polled it already.
boost::asio::awaitable<ModelCheck> check_model(CommissionBus& bus, CommissionedSensor& sensor,
                                               const bool& stopping);

// What the check found, for the command to print on stderr ("tiltgate info: ..."); empty when
// there is nothing to say (a family of one model, a silent sensor, a named model that measures).
std::string model_check_message(const CommissionedSensor& sensor, const ModelCheck& check);

// What a poll came to, for the user: the no-reply message with its hint, "address 101
// answered, but refused the measurement as model M: <the driver's refusal text>", "address 101
// answered, but gave no usable reading as model M"; empty for a reading.
std::string poll_outcome_message(const CommissionBus& bus, const CommissionedSensor& sensor,
                                 const PollOutcome& outcome);

// The same in a few words, for `info`'s "status:" line: "no reply", "refused: NAK 2 (...)".
std::string poll_status_text(const CommissionedSensor& sensor, const PollOutcome& outcome);

// The sensor as its driver holds it after a poll that came to `outcome`, for the event.
SensorReadingEvent sensor_reading(const CommissionedSensor& sensor, const PollOutcome& outcome);

}  // namespace tiltgate
