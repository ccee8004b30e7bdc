// `tiltgate set`: the Configurator's settings for one sensor, through its driver (which unlocks
// and locks again as the protocol needs), then the sensor's state read back as `info` shows it.
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <iostream>

#include "commission/commands.h"
#include "commission/commission_run.h"
#include "gateway/driver_registry.h"
#include "commission/model_detection.h"
#include "commission/reading_format.h"
#include "commission/set_config_update.h"
#include "commission/set_plan.h"

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

std::string value_text(double value) { return fmt::format("{}", value); }

// What a running gateway that owns the bus could not be told (commission/commission_bus.h).
void warn(const std::optional<std::string>& warning) {
  if (warning) std::cerr << "warning: " << *warning << "\n";
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

// The writes the words stand for on this sensor's model, every value checked before anything
// is sent; an exit code (2) with the reason printed when they cannot be made.
Expected<SetPlan, int> plan_for(const CommissionBus& bus, FamilyCommandsList commands,
                                const CommissionedSensor& sensor,
                                const SetArguments& arguments) {
  const auto target = set_target(bus.families(), commands, bus.config(), sensor.config);
  if (!target) {
    std::cerr << "tiltgate set: " << target.error() << "\n";
    return Unexpected{2};
  }
  auto plan = plan_setting(*target, arguments);
  if (!plan) {
    std::cerr << "tiltgate set: " << plan.error() << "\n";
    return Unexpected{2};
  }
  if (auto checked = sensor.driver->check_writes(plan->writes); !checked) {
    std::cerr << fmt::format("tiltgate set: {}: {}; nothing was sent", plan->setting,
                             checked.error().detail);
    for (const SettingWrite& w : plan->writes)
      if (!sensor.driver->check_write(w.target, w.value))
        std::cerr << descriptor_range(*target, w.target);
    std::cerr << "\n";
    return Unexpected{2};
  }
  if (plan->new_address == sensor.config.address) {
    std::cerr << fmt::format("tiltgate set: the sensor is at address {} already\n",
                             sensor.config.address);
    return Unexpected{2};
  }
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

void print_settings(const SetPlan& plan, const SensorState& state) {
  for (std::size_t i = 0; i < plan.writes.size(); ++i) {
    const WriteTarget target = plan.writes[i].target;
    if (target == WriteTarget::command) continue;
    std::optional<double> value = state.settings.get(target);
    if (target.is_device_value() && state.reading &&
        target.device_index() < state.reading->device_values.size())
      value = state.reading->device_values[target.device_index()];
    std::cout << fmt::format("{:<11} {}\n", plan.write_names[i] + ":",
                             value ? value_text(*value) : "-");
  }
}

asio::awaitable<int> set_work(CommissionBus& bus, const bool& stopping, const BusOptions& options,
                              const SetArguments& arguments, FamilyCommandsList commands) {
  if (bus.sensors().size() != 1) {
    std::cerr << "tiltgate set: give one sensor (--address A, or --config FILE --sensor NAME)\n";
    co_return 2;
  }
  CommissionedSensor& sensor = bus.sensors().front();
  // Checked as the model the options give first, so that a usage error costs no bus time.
  auto plan = plan_for(bus, commands, sensor, arguments);
  if (!plan) co_return plan.error();
  const std::uint32_t old_address = sensor.config.address;

  // The sensor must answer before it is changed (a refusal is an answer), as the model it is,
  // and a new address must be free.
  const ModelCheck check = co_await check_model(bus, sensor, stopping);
  if (stopping) co_return 0;
  if (const std::string found = model_check_message(sensor, check); !found.empty())
    std::cerr << "tiltgate set: " << found << "\n";
  if (check.outcome().result == PollResult::silent && !sensor.driver->state().identity_known) {
    std::cerr << "tiltgate set: " << bus.no_reply_message(sensor) << "\nnothing was sent\n";
    co_return 1;
  }
  if (check.adopted) {
    plan = plan_for(bus, commands, sensor, arguments);
    if (!plan) co_return plan.error();
  }
  if (plan->new_address) {
    if (const auto other = co_await someone_at(bus, sensor, *plan->new_address)) {
      std::cerr << fmt::format(
          "tiltgate set: address {} is taken: a sensor already answers there ({}); nothing was "
          "changed\n",
          *plan->new_address, *other);
      co_return 1;
    }
  }

  // A gateway that polls this sensor waits while it moves (released when the command ends).
  if (plan->new_address) warn(bus.address_changing(old_address));
  for (std::size_t i = 0; i < plan->writes.size() && !stopping; ++i) {
    const SettingWrite& w = plan->writes[i];
    const WriteResult result = co_await sensor.driver->write(bus.line(), w.target, w.value);
    if (stopping) co_return 0;
    if (!result) {
      // A running gateway records the refusal or the silence in its audit trail.
      warn(bus.setting_changed(sensor.config.address, w.target, w.value, result,
                               sensor.driver->state().counters.last_refusal));
      sensor.driver->abandon(std::span(plan->writes).first(i));
      std::cerr << fmt::format("tiltgate set: {} := {} at address {}: {} ({})\n",
                               plan->write_names[i], value_text(w.value), sensor.config.address,
                               meaning(result.error()), result.error().detail);
      if (result.error().kind == WriteErrorKind::no_response)
        std::cerr << bus.no_reply_message(sensor) << "\n";
      co_return 1;
    }
    // A running gateway keeps the sensor's settings record (a move is followed below).
    if (w.target != WriteTarget::bus_address)
      warn(bus.setting_changed(sensor.config.address, w.target, w.value, result, std::nullopt));
  }
  if (stopping) co_return 0;
  std::cout << fmt::format("{}{} at address {}: acknowledged\n", fmt::join(arguments.words, " "),
                           arguments.permanent ? " --permanent" : "", old_address);
  if (plan->new_address) {
    if (const auto followed = bus.address_changed(old_address, *plan->new_address); !followed)
      warn(followed.error());
    else if (!followed->empty())
      std::cout << fmt::format("gateway: sensor {} is polled at address {} from now on\n",
                               *followed, *plan->new_address);
    sensor.config.address = *plan->new_address;
    std::cout << fmt::format("the sensor now answers at address {}\n", *plan->new_address);
  }
  if (plan->new_baud && bus.through_gateway()) {
    // The gateway's bus keeps its rate: the sensor has left it until the bus is moved too.
    std::cout << fmt::format("the sensor restarted at {} baud; the gateway's bus stays at {} "
                             "baud, so it no longer answers there: set the others, then the "
                             "bus's baud in the configuration\n",
                             *plan->new_baud, bus.config().baud);
  } else if (plan->new_baud) {
    if (auto reopened = bus.reopen_at(*plan->new_baud); !reopened) {
      std::cerr << "tiltgate set: " << reopened.error() << "\n";
      co_return 1;
    }
    std::cout << fmt::format("the sensor restarted at {} baud; the line follows it\n",
                             *plan->new_baud);
  } else if (plan->restarts) {
    std::cout << "the sensor restarted\n";
  }
  int exit_code = 0;
  if (const auto updated = update_config_file(options, sensor.config, old_address, *plan)) {
    if (*updated) std::cout << **updated << "\n";
  } else {
    std::cerr << "tiltgate set: " << updated.error() << "\n";
    exit_code = 1;
  }
  if (plan->new_baud && bus.through_gateway()) co_return exit_code;  // nothing to read it back on

  // Read back: after a restart the sensor gets time to come back.
  const auto deadline = std::chrono::steady_clock::now() + kRestartWait;
  const PollOutcome read = plan->restarts
                               ? co_await read_back(bus, sensor, stopping, 1'000'000, deadline)
                               : co_await read_back(bus, sensor, stopping, kMaxIdentityPolls, deadline);
  if (stopping) co_return 0;
  std::cout << "\n";
  if (read.result != PollResult::reading) {
    std::cout << "address:    " << sensor.config.address
              << "\nstatus:     " << poll_status_text(sensor, read) << "\n";
    std::cerr << "tiltgate set: the change was acknowledged, but reading back: "
              << poll_outcome_message(bus, sensor, read) << "\n";
    co_return 1;
  }
  std::cout << sensor_info_text(sensor.config.address, sensor.driver->model(),
                                sensor.driver->state());
  print_settings(*plan, sensor.driver->state());
  std::cout.flush();
  co_return exit_code;
}

int set_command(const BusOptions& options, const SetArguments& arguments, FamilyList families,
                FamilyCommandsList commands) {
  return run_commissioning("set", options, families,
                           [&](CommissionBus& bus, const bool& stopping) -> asio::awaitable<int> {
                             co_return co_await set_work(bus, stopping, options, arguments,
                                                         commands);
                           });
}

}  // namespace

Subcommand add_set(CLI::App& app, FamilyList families, FamilyCommandsList commands) {
  auto bus = std::make_shared<BusOptions>();
  auto arguments = std::make_shared<SetArguments>();
  CLI::App* set = app.add_subcommand("set", "change one setting of a sensor (address, baud, "
                                            "filter, zero, restart, the model's own) and read it "
                                            "back");
  add_bus_options(*set, *bus, families);
  // One address, so that the SETTING words after it are not taken for more addresses.
  set->get_option("--address")->allow_extra_args(false);
  set->add_option("setting", arguments->words, "SETTING [VALUE...]")->required();
  set->add_flag("--permanent", arguments->permanent, "zero-here: keep the zero after a restart");
  set->footer(set_help_footer(commands));
  return {set,
          [bus, arguments, families, commands] {
            return set_command(*bus, *arguments, families, commands);
          },
          true};
}

}  // namespace tiltgate
