#include "commission/info_engine.h"

#include <algorithm>
#include <fmt/format.h>

#include "commission/model_detection.h"

namespace tiltgate {

namespace {

namespace asio = boost::asio;

// What a sensor without its driver says of itself; the exit code: 0 when it told something.
asio::awaitable<int> self_report(CommissionBus& bus, const CommissionedSensor& sensor,
                                 const FamilyCommands& family, const EventSink& report) {
  const SelfReport told =
      co_await family.identify.ask(bus.line(), bus.config().protocol, sensor.config.address);
  SensorReadingEvent reading;
  reading.address = sensor.config.address;
  reading.result = told.answered ? PollResult::no_reading : PollResult::silent;
  reading.status = told.answered ? "answered" : "no reply";
  reading.polled = std::chrono::system_clock::now();
  reading.self_report = told.text;
  report(reading);
  if (!told.answered) {
    report(FailedEvent{1, bus.no_reply_message(sensor)});
    co_return 1;
  }
  if (!told.identified) {
    report(FailedEvent{1, fmt::format("address {} answered, but told nothing of itself; give its "
                                      "profile (--device) to read its values",
                                      sensor.config.address)});
    co_return 1;
  }
  co_return 0;
}

// A sensor through its driver, its model checked first; the exit code: 0 when it told its
// identity and gave a reading.
asio::awaitable<int> driver_report(CommissionBus& bus, CommissionedSensor& sensor,
                                   const EventSink& report, const bool& stopping) {
  const ModelCheck check = co_await check_model(bus, sensor, stopping);
  if (stopping) co_return 0;
  if (const std::string found = model_check_message(sensor, check); !found.empty())
    report(NoteEvent{false, found});
  const PollOutcome outcome = check.outcome();
  report(sensor_reading(sensor, outcome));
  if (outcome.result != PollResult::reading) {
    report(FailedEvent{1, poll_outcome_message(bus, sensor, outcome)});
    co_return 1;
  }
  if (!sensor.driver->state().identity_known) {
    // It measures, but did not tell its serial and firmware: shown as "-".
    report(FailedEvent{1, fmt::format("address {} gave a reading, but not its identity "
                                      "(serial, firmware)",
                                      sensor.config.address)});
    co_return 1;
  }
  co_return 0;
}

}  // namespace

asio::awaitable<int> show_info(CommissionBus& bus, FamilyCommandsList commands,
                               const EventSink& report, const bool& stopping) {
  const FamilyCommands* family =
      find_commands(commands, find_protocol(bus.families(), bus.config().protocol).family);
  const bool without_drivers = std::any_of(bus.sensors().begin(), bus.sensors().end(),
                                           [](const auto& s) { return !s.driver; });
  // Without a driver only the protocol's own requests can ask; a family without them needs
  // the options that make its driver, whichever sensor it is.
  if (without_drivers && (!family || !family->identify.ask)) {
    report(FailedEvent{2, fmt::format("a {} sensor is known by its driver only; give what it "
                                      "needs (--device)",
                                      bus.config().protocol)});
    co_return 2;
  }
  int exit_code = 0;
  for (CommissionedSensor& sensor : bus.sensors()) {
    const int sensor_code = sensor.driver
                                ? co_await driver_report(bus, sensor, report, stopping)
                                : co_await self_report(bus, sensor, *family, report);
    if (stopping) co_return 0;
    exit_code = std::max(exit_code, sensor_code);
  }
  co_return exit_code;
}

}  // namespace tiltgate
