// `tiltgate info`: the vendor User App's Sensor Info, for each sensor asked for. A sensor whose
// model the options do not name is polled as each model of its family until one measures
// (commission/model_detection.h). A sensor without its driver (a device whose family needs a
// --device profile, given none) shows what it says of itself when asked with its protocol's
// own requests (FamilyCommands::identify).
#include <fmt/format.h>

#include <algorithm>
#include <iostream>

#include "commission/commands.h"
#include "commission/commission_run.h"
#include "commission/model_detection.h"
#include "commission/reading_format.h"

namespace tiltgate {

namespace {

// What a sensor without its driver says of itself; the exit code: 0 when it told something.
boost::asio::awaitable<int> self_report(CommissionBus& bus, const CommissionedSensor& sensor,
                                        FamilyCommandsList commands) {
  const FamilyCommands* family =
      find_commands(commands, find_protocol(bus.families(), bus.config().protocol).family);
  if (!family || !family->identify.ask) {
    std::cerr << fmt::format("tiltgate info: a {} sensor is known by its driver only; give what "
                             "it needs (--device)\n",
                             bus.config().protocol);
    co_return 2;
  }
  const SelfReport report = co_await family->identify.ask(bus.line(), bus.config().protocol,
                                                             sensor.config.address);
  std::cout << "address:    " << sensor.config.address << "\n" << report.text;
  if (!report.answered) {
    std::cout << "status:     no reply\n";
    std::cerr << "tiltgate info: " << bus.no_reply_message(sensor) << "\n";
    co_return 1;
  }
  if (!report.identified) {
    std::cerr << fmt::format("tiltgate info: address {} answered, but told nothing of itself; "
                             "give its profile (--device) to read its values\n",
                             sensor.config.address);
    co_return 1;
  }
  co_return 0;
}

int info_command(const BusOptions& options, FamilyList families, FamilyCommandsList commands) {
  return run_commissioning(
      "info", options, families,
      [commands](CommissionBus& bus, const bool& stopping) -> boost::asio::awaitable<int> {
        int exit_code = 0;
        bool first = true;
        for (CommissionedSensor& sensor : bus.sensors()) {
          if (!sensor.driver) {
            if (!first) std::cout << "\n";
            first = false;
            exit_code = std::max(exit_code, co_await self_report(bus, sensor, commands));
            if (stopping) co_return 0;
            continue;
          }
          const ModelCheck check = co_await check_model(bus, sensor, stopping);
          if (stopping) co_return 0;
          if (const std::string found = model_check_message(sensor, check); !found.empty())
            std::cerr << "tiltgate info: " << found << "\n";
          if (!first) std::cout << "\n";
          first = false;
          const SensorState& state = sensor.driver->state();
          const PollOutcome outcome = check.outcome();
          if (outcome.result == PollResult::reading && state.identity_known) {
            std::cout << sensor_info_text(sensor.config.address, sensor.driver->model(), state);
            continue;
          }
          exit_code = 1;
          if (outcome.result == PollResult::reading) {
            // It measures, but did not tell its serial and firmware: shown as "-".
            std::cout << sensor_info_text(sensor.config.address, sensor.driver->model(), state);
            std::cerr << fmt::format("tiltgate info: address {} gave a reading, but not its "
                                     "identity (serial, firmware)\n",
                                     sensor.config.address);
            continue;
          }
          std::cout << "address:    " << sensor.config.address
                    << "\nstatus:     " << poll_status_text(sensor, outcome) << "\n";
          std::cerr << "tiltgate info: " << poll_outcome_message(bus, sensor, outcome) << "\n";
        }
        std::cout.flush();
        co_return exit_code;
      });
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
