#include "commission/set_engine.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "commission/event_text.h"
#include "commission/model_detection.h"
#include "commission/set_config_update.h"
#include "gateway/driver_registry.h"

namespace tiltgate {

namespace {

namespace asio = boost::asio;

// How long a restarted sensor gets to answer again. Neither family's manual gives its boot
// time; a poll that times out meanwhile costs only its reply time-out.
constexpr auto kRestartWait = std::chrono::seconds(10);

std::string meaning(const WriteError& error) {
  switch (error.kind) {
    case WriteErrorKind::not_supported: return "the sensor has no such setting";
    case WriteErrorKind::bad_value: return "the value is out of range";
    case WriteErrorKind::rejected: return "the sensor refused the value";
    case WriteErrorKind::refused: return "the sensor refused the change";
    case WriteErrorKind::busy: return "the sensor stayed busy";
    case WriteErrorKind::no_response: return "no reply";
    case WriteErrorKind::device_exception:
      return fmt::format("the device answered with Modbus exception {:#04x}", error.device_exception);
  }
  return "failed";
}

// The range a refused value must be in, from the model's descriptor, where it says one.
std::string descriptor_range(const SetTarget& target, WriteTarget id) {
  for (const SettingDescriptor& s : target.model->settings)
    if (s.id == id) return fmt::format(" ({} accepts {})", s.name, range_text(s));
  if (id.is_device_value() && id.device_index() < target.device_values.size()) {
    const DeviceValue& v = target.device_values[id.device_index()];
    return fmt::format(" ({} accepts {}..{})", v.name, v.min, v.max);
  }
  return "";
}

Expected<SetTarget, std::string> set_target(FamilyList families, FamilyCommandsList commands,
                                            const BusConfig& bus,
                                            const SensorConfig& sensor) {
  const ModelEntry model = find_model(families, sensor.model);
  const ProtocolEntry protocol = find_protocol(families, bus.protocol);
  if (!model.model || !protocol.protocol)
    return Unexpected{fmt::format("no family has model {} on a {} bus", sensor.model, bus.protocol)};
  const FamilyCommands* family_commands = find_commands(commands, model.family);
  if (!family_commands)
    return Unexpected{fmt::format("no commands for model {}'s family", sensor.model)};
  return SetTarget{family_commands, protocol.protocol, model.model,
                   sensor.family_options.device_values()};
}

// The writes the words stand for on this sensor's model, every value checked before anything
// is sent; why (exit code 2) when they cannot be made.
Expected<SetPlan, FailedEvent> plan_for(const CommissionBus& bus, FamilyCommandsList commands,
                                        const CommissionedSensor& sensor,
                                        const SetArguments& arguments) {
  const auto target = set_target(bus.families(), commands, bus.config(), sensor.config);
  if (!target) return Unexpected{FailedEvent{2, target.error()}};
  auto plan = plan_setting(*target, arguments);
  if (!plan) return Unexpected{FailedEvent{2, plan.error()}};
  if (auto checked = sensor.driver->check_writes(plan->writes); !checked) {
    std::string message =
        fmt::format("{}: {}; nothing was sent", plan->setting, checked.error().detail);
    for (const SettingWrite& w : plan->writes)
      if (!sensor.driver->check_write(w.target, w.value))
        message += descriptor_range(*target, w.target);
    return Unexpected{FailedEvent{2, message}};
  }
  if (plan->new_address == sensor.config.address)
    return Unexpected{FailedEvent{
        2, fmt::format("the sensor is at address {} already", sensor.config.address)}};
  return std::move(*plan);
}

// Whether a sensor answers at `address` on the bus: one poll through a driver for it.
asio::awaitable<std::optional<std::string>> someone_at(CommissionBus& bus,
                                                       const CommissionedSensor& sensor,
                                                       std::uint32_t address) {
  SensorConfig there = sensor.config;
  there.address = address;
  there.name = fmt::format("probe {}", address);
  auto probe = make_driver(bus.families(), there, bus.config());
  if (!probe) co_return std::nullopt;
  co_await probe->poll(bus.line());
  const SensorState& state = probe->state();
  if (!state.online && !state.identity_known) co_return std::nullopt;
  co_return state.serial.empty() ? std::string("serial unknown") : "serial " + state.serial;
}

// The sensor must answer before it is changed (a refusal is an answer), as the model it is,
// and a new address must be free. The plan again for a model the check adopted; the exit code
// when the change cannot go on (0 when stopping).
asio::awaitable<Expected<SetPlan, int>> check_before(CommissionBus& bus, FamilyCommandsList commands,
                                                     CommissionedSensor& sensor, SetPlan plan,
                                                     const SetArguments& arguments,
                                                     const EventSink& report,
                                                     const bool& stopping) {
  const ModelCheck check = co_await check_model(bus, sensor, stopping);
  if (stopping) co_return Unexpected{0};
  if (const std::string found = model_check_message(sensor, check); !found.empty())
    report(NoteEvent{false, found});
  if (check.outcome().result == PollResult::silent && !sensor.driver->state().identity_known) {
    report(FailedEvent{1, bus.no_reply_message(sensor) + "\nnothing was sent"});
    co_return Unexpected{1};
  }
  if (check.adopted) {
    auto adopted = plan_for(bus, commands, sensor, arguments);
    if (!adopted) {
      report(adopted.error());
      co_return Unexpected{adopted.error().exit_code};
    }
    plan = std::move(*adopted);
  }
  if (plan.new_address) {
    if (const auto other = co_await someone_at(bus, sensor, *plan.new_address)) {
      report(FailedEvent{1, fmt::format("address {} is taken: a sensor already answers there "
                                        "({}); nothing was changed",
                                        *plan.new_address, *other)});
      co_return Unexpected{1};
    }
  }
  co_return plan;
}

// The sensor's answer to one write, as the event tells it.
SettingAcknowledgedEvent answer_of(const CommissionedSensor& sensor, const std::string& name,
                                   std::optional<double> old_value, const SettingWrite& write,
                                   const WriteResult& result) {
  SettingAcknowledgedEvent answer{sensor.config.address, name, old_value, write.value, "ack",
                                  std::nullopt, ""};
  if (result) return answer;
  const WriteError& error = result.error();
  answer.detail = fmt::format("{} ({})", meaning(error), error.detail);
  if (error.kind == WriteErrorKind::no_response) {
    answer.result = "timeout";
  } else if (error.kind == WriteErrorKind::device_exception) {
    answer.result = "nak";
    answer.refusal_code = error.device_exception;
  } else if (error.kind == WriteErrorKind::rejected || error.kind == WriteErrorKind::refused) {
    answer.result = "nak";
    answer.refusal_code = sensor.driver->state().counters.last_refusal;
  } else {
    answer.result = "failed";
  }
  return answer;
}

// The plan's writes in turn, each answer reported; the exit code: 0 when every one was
// acknowledged (or `stopping` turned true), 1 at the first that was not.
asio::awaitable<int> write_all(CommissionBus& bus, CommissionedSensor& sensor,
                               const SetPlan& plan, const EventSink& report,
                               const bool& stopping) {
  for (std::size_t i = 0; i < plan.writes.size() && !stopping; ++i) {
    const SettingWrite& w = plan.writes[i];
    const std::optional<double> old_value = sensor.driver->state().settings.get(w.target);
    const WriteResult result = co_await sensor.driver->write(bus.line(), w.target, w.value);
    if (stopping) co_return 0;
    report(answer_of(sensor, plan.write_names[i], old_value, w, result));
    // A running gateway records the refusal or the silence in its audit trail, and keeps the
    // sensor's settings record (a move is followed by the caller).
    if (!result || w.target != WriteTarget::bus_address) {
      const auto refusal = result ? std::nullopt : sensor.driver->state().counters.last_refusal;
      if (auto warning = bus.setting_changed(sensor.config.address, w.target, w.value, result,
                                             refusal))
        report(GatewayWarningEvent{std::move(*warning)});
    }
    if (result) continue;
    sensor.driver->abandon(std::span(plan.writes).first(i));
    std::string message =
        fmt::format("{} := {} at address {}: {} ({})", plan.write_names[i],
                    setting_value_text(w.value), sensor.config.address,
                    meaning(result.error()), result.error().detail);
    if (result.error().kind == WriteErrorKind::no_response)
      message += "\n" + bus.no_reply_message(sensor);
    report(FailedEvent{1, message});
    co_return 1;
  }
  co_return 0;
}

// After every write was acknowledged: the sensor followed to its new address and rate, and the
// configuration file it came from with it. The exit code: 1 when the line could not follow it
// (the end) or the file not (`go_on` stays true).
int follow_change(CommissionBus& bus, CommissionedSensor& sensor, const SetPlan& plan,
                  const SetRequest& request, const EventSink& report, bool& go_on) {
  const std::uint32_t old_address = sensor.config.address;
  report(SettingAppliedEvent{fmt::format("{}", fmt::join(request.arguments.words, " ")),
                             request.arguments.permanent, old_address});
  if (plan.new_address) {
    AddressMovedEvent moved{old_address, *plan.new_address, ""};
    if (auto followed = bus.address_changed(old_address, *plan.new_address))
      moved.gateway_sensor = std::move(*followed);
    else
      report(GatewayWarningEvent{std::move(followed.error())});
    sensor.config.address = *plan.new_address;
    report(moved);
  }
  if (plan.new_baud && bus.through_gateway()) {
    report(SensorRestartedEvent{plan.new_baud, false, bus.config().baud});
  } else if (plan.new_baud) {
    if (auto reopened = bus.reopen_at(*plan.new_baud); !reopened) {
      report(FailedEvent{1, reopened.error()});
      go_on = false;
      return 1;
    }
    report(SensorRestartedEvent{plan.new_baud, true, bus.config().baud});
  } else if (plan.restarts) {
    report(SensorRestartedEvent{std::nullopt, true, bus.config().baud});
  }
  const auto updated = update_config_file(request.config_file, sensor.config, old_address, plan);
  if (!updated) {
    report(FailedEvent{1, updated.error()});
    return 1;
  }
  if (!updated->empty()) report(ConfigUpdatedEvent{request.config_file, *updated});
  return 0;
}

// Polls until the sensor has told its identity and given a new reading (one from before the
// change does not count), `polls` times at most or until `deadline`, whichever comes first.
// The last poll's outcome: a reading only with the identity known.
asio::awaitable<PollOutcome> read_back(CommissionBus& bus, CommissionedSensor& sensor,
                                       const bool& stopping, int polls,
                                       std::chrono::steady_clock::time_point deadline) {
  PollOutcome outcome;
  for (int poll = 0; poll < polls && !stopping; ++poll) {
    const PollMark before = mark_before_poll(sensor.driver->state());
    co_await sensor.driver->poll(bus.line());
    outcome = outcome_since(before, sensor.driver->state());
    if (outcome.result == PollResult::reading && sensor.driver->state().identity_known)
      co_return outcome;
    if (std::chrono::steady_clock::now() >= deadline) break;
  }
  if (outcome.result == PollResult::reading) outcome.result = PollResult::no_reading;
  co_return outcome;
}

// The values the plan wrote, as the sensor's state now holds them.
SettingsReadEvent settings_read(const CommissionedSensor& sensor, const SetPlan& plan) {
  const SensorState& state = sensor.driver->state();
  SettingsReadEvent read{sensor.config.address, {}};
  for (std::size_t i = 0; i < plan.writes.size(); ++i) {
    const WriteTarget target = plan.writes[i].target;
    if (target == WriteTarget::command) continue;
    std::optional<double> value = state.settings.get(target);
    if (target.is_device_value() && state.reading &&
        target.device_index() < state.reading->device_values.size())
      value = state.reading->device_values[target.device_index()];
    read.settings.push_back({plan.write_names[i], value});
  }
  return read;
}

// Reads the sensor back after the change (after a restart it gets time to come back); the exit
// code: 1 when it could not be.
asio::awaitable<int> report_read_back(CommissionBus& bus, CommissionedSensor& sensor,
                                      const SetPlan& plan, const EventSink& report,
                                      const bool& stopping) {
  const auto deadline = std::chrono::steady_clock::now() + kRestartWait;
  const int polls = plan.restarts ? 1'000'000 : kMaxIdentityPolls;
  const PollOutcome read = co_await read_back(bus, sensor, stopping, polls, deadline);
  if (stopping) co_return 0;
  report(sensor_reading(sensor, read));
  if (read.result != PollResult::reading) {
    report(FailedEvent{1, "the change was acknowledged, but reading back: " +
                              poll_outcome_message(bus, sensor, read)});
    co_return 1;
  }
  report(settings_read(sensor, plan));
  co_return 0;
}

}  // namespace

asio::awaitable<int> set_sensor(CommissionBus& bus, const SetRequest& request,
                                FamilyCommandsList commands, const EventSink& report,
                                const bool& stopping) {
  if (bus.sensors().size() != 1) {
    report(FailedEvent{2, "give one sensor (--address A, or --config FILE --sensor NAME)"});
    co_return 2;
  }
  CommissionedSensor& sensor = bus.sensors().front();
  // Checked as the model the options give first, so that a usage error costs no bus time.
  auto plan = plan_for(bus, commands, sensor, request.arguments);
  if (!plan) {
    report(plan.error());
    co_return plan.error().exit_code;
  }
  auto checked = co_await check_before(bus, commands, sensor, std::move(*plan),
                                       request.arguments, report, stopping);
  if (!checked) co_return checked.error();
  // A gateway that polls this sensor waits while it moves (released when the command ends).
  if (checked->new_address)
    if (auto warning = bus.address_changing(sensor.config.address))
      report(GatewayWarningEvent{std::move(*warning)});
  if (const int written = co_await write_all(bus, sensor, *checked, report, stopping);
      written != 0 || stopping)
    co_return written;
  bool go_on = true;
  const int followed = follow_change(bus, sensor, *checked, request, report, go_on);
  // Through the gateway at a new rate there is nothing to read it back on.
  if (!go_on || (checked->new_baud && bus.through_gateway())) co_return followed;
  const int read = co_await report_read_back(bus, sensor, *checked, report, stopping);
  if (stopping) co_return 0;
  co_return read != 0 ? read : followed;
}

}  // namespace tiltgate
