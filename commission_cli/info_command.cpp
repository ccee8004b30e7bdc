// `tiltgate info` on the command line: the engine's Sensor Info (commission/info_engine.h) shown
// as text, one block of lines per sensor with a blank line between, and what a sensor did not
// tell as "tiltgate info: ..." on stderr.
#include <iostream>

#include "commission_cli/commands.h"
#include "commission_cli/commission_run.h"
#include "commission/event_text.h"
#include "commission/info_engine.h"

namespace tiltgate {

namespace {

// The events as the command line shows them; stdout is flushed once, at the end.
class InfoText {
 public:
  void operator()(const CommissionEvent& event) {
    if (const auto* reading = std::get_if<SensorReadingEvent>(&event)) {
      if (shown_++ > 0) std::cout << "\n";
      std::cout << sensor_reading_text(*reading);
    } else if (const auto* failed = std::get_if<FailedEvent>(&event)) {
      std::cerr << "tiltgate info: " << failed->message << "\n";
    } else if (const auto* note = std::get_if<NoteEvent>(&event)) {
      std::cerr << "tiltgate info: " << (note->warning ? "warning: " : "") << note->text << "\n";
    }
  }

 private:
  int shown_ = 0;  // sensors shown so far
};

// After a gateway's run, as after the work on a tty of the command's own.
int flushed(int exit_code) {
  std::cout.flush();
  return exit_code;
}

int info_command(const BusOptions& options, FamilyList families, FamilyCommandsList commands) {
  InfoText text;
  const EventSink report = [&text](const CommissionEvent& event) { text(event); };
  return run_commissioning(
      "info", options, families,
      [commands, &report](CommissionBus& bus, const bool& stopping) -> boost::asio::awaitable<int> {
        const int exit_code = co_await show_info(bus, commands, report, stopping);
        std::cout.flush();
        co_return exit_code;
      },
      GatewayRequest{CommandRequest{"info", options, {}, {}, {}, {}}, report, flushed});
}

}  // namespace

Subcommand add_info(CLI::App& app, FamilyList families, FamilyCommandsList commands) {
  auto bus = std::make_shared<BusOptions>();
  CLI::App* info = app.add_subcommand("info", "show a sensor's address, model, serial, firmware, "
                                              "lock level and angles (the User App's Sensor Info)");
  add_bus_options(*info, *bus, families);
  bus->driver_optional = true;  // a device without its profile: what it says of itself
  info->footer(info_help_footer(commands));
  return {info, [bus, families, commands] { return info_command(*bus, families, commands); },
          true};
}

}  // namespace tiltgate
