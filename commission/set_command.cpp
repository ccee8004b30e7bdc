// `tiltgate set` on the command line: the engine's change of one setting (commission/
// set_engine.h) shown as text: what was acknowledged, the move and the restart, the
// configuration file that followed, and the sensor read back as `info` shows it.
#include <iostream>

#include "commission/commands.h"
#include "commission/commission_run.h"
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

int set_command(const BusOptions& options, const SetArguments& arguments, FamilyList families,
                FamilyCommandsList commands) {
  const SetRequest request{arguments, followed_config_file(options)};
  return run_commissioning("set", options, families,
                           [&](CommissionBus& bus, const bool& stopping) -> asio::awaitable<int> {
                             const EventSink report = show_set_event;
                             const int exit_code =
                                 co_await set_sensor(bus, request, commands, report, stopping);
                             std::cout.flush();
                             co_return exit_code;
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
