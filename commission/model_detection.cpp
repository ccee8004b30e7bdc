#include "commission/model_detection.h"

#include <fmt/format.h>

#include "commission/reading_format.h"
#include "gateway/driver_registry.h"

namespace tiltgate {

namespace {

bool complete(const SensorState& state) { return state.identity_known && state.reading; }

// Where the model a sensor was given came from, for messages.
std::string_view named_by(ModelSource source) {
  return source == ModelSource::option ? "--model names" : "the configuration names";
}

}  // namespace

boost::asio::awaitable<PollOutcome> poll_for_identity(Line& line, SensorDriver& driver,
                                                      const bool& stopping) {
  PollOutcome outcome;
  for (int poll = 0; poll < kMaxIdentityPolls && !stopping; ++poll) {
    const PollMark before = mark_before_poll(driver.state());
    co_await driver.poll(line);
    outcome = outcome_since(before, driver.state());
    if (outcome.result == PollResult::silent || complete(driver.state())) break;
  }
  co_return outcome;
}

boost::asio::awaitable<ModelCheck> check_model(CommissionBus& bus, CommissionedSensor& sensor,
                                               const bool& stopping) {
  ModelCheck check;
  check.polled_as = sensor.config.model;
  const ModelEntry entry = find_model(bus.families(), sensor.config.model);
  // Only the models that speak the bus's protocol can be the sensor's.
  if (entry.family) {
    for (const ModelDescriptor& model : entry.family->models)
      if (model.speaks(bus.config().protocol)) ++check.family_models;
  }
  check.polled = co_await poll_for_identity(bus.line(), *sensor.driver, stopping);
  if (check.polled.result == PollResult::reading) {
    check.measured_as = sensor.config.model;
    co_return check;
  }
  // Silence says nothing of the model; another model's requests would go unanswered too.
  if (check.polled.result == PollResult::silent || stopping) co_return check;
  check.polled_refusal = check.polled.result == PollResult::refused
                             ? sensor.driver->refusal_text(check.polled.refusal)
                             : std::string("with no usable reading");
  if (!entry.family) co_return check;
  for (const ModelDescriptor& model : entry.family->models) {
    if (model.name == sensor.config.model || !model.speaks(bus.config().protocol)) continue;
    SensorConfig as_other = sensor.config;
    as_other.model = std::string(model.name);
    auto driver = make_driver(bus.families(), as_other, bus.config());
    if (!driver) continue;
    const PollOutcome outcome = co_await poll_for_identity(bus.line(), *driver, stopping);
    if (stopping) co_return check;
    if (outcome.result != PollResult::reading) continue;
    check.measured_as = as_other.model;
    if (sensor.model_source == ModelSource::detected) {
      sensor.config = std::move(as_other);
      sensor.driver = std::move(driver);
      check.adopted = true;
    }
    co_return check;
  }
  co_return check;
}

std::string model_check_message(const CommissionedSensor& sensor, const ModelCheck& check) {
  if (check.family_models < 2) return "";
  const std::uint32_t address = sensor.config.address;
  if (sensor.model_source == ModelSource::detected) {
    if (check.measured_as.empty()) return "";
    if (!check.adopted) return fmt::format("address {}: model {} (detected)", address, check.measured_as);
    return fmt::format("address {}: model {} (detected: polled as model {}, it answered {})",
                       address, check.measured_as, check.polled_as, check.polled_refusal);
  }
  if (check.measured_as.empty() || check.measured_as == check.polled_as) return "";
  return fmt::format("address {} measures as model {}, not as the {} that {} (it answered {}); "
                     "going on as {}",
                     address, check.measured_as, check.polled_as, named_by(sensor.model_source),
                     check.polled_refusal, check.polled_as);
}

std::string poll_outcome_message(const CommissionBus& bus, const CommissionedSensor& sensor,
                                 const PollOutcome& outcome) {
  switch (outcome.result) {
    case PollResult::reading: return "";
    case PollResult::silent: return bus.no_reply_message(sensor);
    case PollResult::refused:
      return fmt::format("address {} answered, but refused the measurement as model {}: {}",
                         sensor.config.address, sensor.config.model,
                         sensor.driver->refusal_text(outcome.refusal));
    case PollResult::no_reading:
      return fmt::format("address {} answered, but gave no usable reading as model {}",
                         sensor.config.address, sensor.config.model);
  }
  return "";
}

std::string poll_status_text(const CommissionedSensor& sensor, const PollOutcome& outcome) {
  switch (outcome.result) {
    case PollResult::silent: return "no reply";
    case PollResult::refused: return "refused: " + sensor.driver->refusal_text(outcome.refusal);
    case PollResult::no_reading: return "no usable reading";
    case PollResult::reading: return "ok";
  }
  return "";
}

SensorReadingEvent sensor_reading(const CommissionedSensor& sensor, const PollOutcome& outcome) {
  SensorReadingEvent reading = reading_of(sensor.config.address, sensor.driver->model(),
                                          sensor.driver->state(), SteadyClock::now());
  reading.result = outcome.result;
  reading.status = poll_status_text(sensor, outcome);
  return reading;
}

}  // namespace tiltgate
