// `tiltgate set` on the command line: the engine's change of one setting (commission/
// set_engine.h) shown as text: what was acknowledged, the move and the restart, the
// configuration file that followed, and the sensor read back as `info` shows it.
#include <iostream>
#include <optional>

#include "commission_cli/commands.h"
#include "commission_cli/commission_run.h"
#include "commission/event_text.h"
#include "commission/set_config_update.h"
#include "commission/set_engine.h"

namespace tiltgate {

namespace {

namespace asio = boost::asio;

// The events as the command line shows them: what was done on stdout (flushed at the end), the
// sensor read back after a blank line; warnings and failures on stderr.
void show_set_event(const CommissionEvent& event) {
  if (const auto* applied = std::get_if<SettingAppliedEvent>(&event)) {
    std::cout << setting_applied_text(*applied);
  } else if (const auto* moved = std::get_if<AddressMovedEvent>(&event)) {
    std::cout << address_moved_text(*moved);
  } else if (const auto* restarted = std::get_if<SensorRestartedEvent>(&event)) {
    std::cout << sensor_restarted_text(*restarted);
  } else if (const auto* updated = std::get_if<ConfigUpdatedEvent>(&event)) {
    std::cout << config_updated_text(*updated);
  } else if (const auto* reading = std::get_if<SensorReadingEvent>(&event)) {
    std::cout << "\n" << sensor_reading_text(*reading);
  } else if (const auto* settings = std::get_if<SettingsReadEvent>(&event)) {
    std::cout << settings_read_text(*settings);
  } else if (const auto* warning = std::get_if<GatewayWarningEvent>(&event)) {
    std::cerr << "warning: " << warning->text << "\n";
  } else if (const auto* failed = std::get_if<FailedEvent>(&event)) {
    std::cerr << "tiltgate set: " << failed->message << "\n";
  } else if (const auto* note = std::get_if<NoteEvent>(&event)) {
    std::cerr << "tiltgate set: " << (note->warning ? "warning: " : "") << note->text << "\n";
  }
}

// What a gateway's `set` moved, for the configuration file the command updates itself: the
// gateway runs the engine, but the file is the engineer's (SetRequest::config_file).
struct MovedThroughGateway {
  std::optional<std::uint32_t> from;
  SetPlan moves;  // new_address, new_baud

  void take(const CommissionEvent& event) {
    if (const auto* moved = std::get_if<AddressMovedEvent>(&event)) {
      from = moved->from;
      moves.new_address = moved->to;
    } else if (const auto* restarted = std::get_if<SensorRestartedEvent>(&event)) {
      moves.new_baud = restarted->baud;
    }
  }
};

// The configuration file follows what the gateway's run moved; the command's exit code.
int follow_in_config(const BusOptions& options, const std::string& config_file,
                     const MovedThroughGateway& moved, FamilyList families, int exit_code) {
  std::cout.flush();
  if (config_file.empty() || (!moved.moves.new_address && !moved.moves.new_baud)) return exit_code;
  const auto target = resolve_bus_options(options, families);
  if (!target || target->sensors.size() != 1) return exit_code;
  SensorConfig sensor = target->sensors.front();
  const auto updated = update_config_file(config_file, sensor, moved.from.value_or(sensor.address),
                                          moved.moves);
  if (!updated) {
    std::cerr << "tiltgate set: " << updated.error() << "\n";
    return exit_code == 0 ? 1 : exit_code;
  }
  if (!updated->empty()) std::cout << config_updated_text({config_file, *updated}) << std::flush;
  return exit_code;
}

int set_command(const BusOptions& options, const SetArguments& arguments, FamilyList families,
                FamilyCommandsList commands) {
  const SetRequest request{arguments, followed_config_file(options)};
  MovedThroughGateway moved;
  const EventSink through_gateway = [&moved](const CommissionEvent& event) {
    moved.take(event);
    show_set_event(event);
  };
  return run_commissioning(
      "set", options, families,
      [&](CommissionBus& bus, const bool& stopping) -> asio::awaitable<int> {
        const EventSink report = show_set_event;
        const int exit_code = co_await set_sensor(bus, request, commands, report, stopping);
        std::cout.flush();
        co_return exit_code;
      },
      GatewayRequest{CommandRequest{"set", options, {}, {}, {}, arguments},
                     through_gateway, [&](int exit_code) {
                       return follow_in_config(options, request.config_file, moved, families,
                                               exit_code);
                     }});
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
