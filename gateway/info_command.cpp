// `tiltgate info`: the vendor User App's Sensor Info, for each sensor asked for.
#include <fmt/format.h>
#include <iostream>

#include "gateway/commands.h"
#include "gateway/commission_run.h"
#include "gateway/reading_format.h"

namespace tiltgate {

namespace {

// A driver reads the identity before the first measurement; a sensor that answered only part
// of that in one poll gets a few more.

bool complete(const SensorState& state) { return state.identity_known && state.reading; }

}  // namespace

int info_command(const BusOptions& options) {
  return run_commissioning(
      "info", options, [](CommissionBus& bus, const bool& stopping) -> boost::asio::awaitable<int> {
        int exit_code = 0;
        bool first = true;
        for (CommissionedSensor& sensor : bus.sensors()) {
          const SensorState& state = sensor.driver->state();
          for (int poll = 0; poll < kMaxIdentityPolls && !stopping; ++poll) {
            co_await sensor.driver->poll(bus.line());
            if (!state.online || complete(state)) break;
          }
          if (stopping) co_return 0;
          if (!first) std::cout << "\n";
          first = false;
          if (!complete(state)) {
            std::cout << "address:    " << sensor.config.address << "\nstatus:     no reply\n";
            std::cerr << "tiltgate info: "
                      << (state.online || state.identity_known
                              ? fmt::format("address {} answered, but gave no complete reading "
                                            "as a {} (is --model right?)",
                                            sensor.config.address, sensor.config.model)
                              : bus.no_reply_message(sensor))
                      << "\n";
            exit_code = 1;
            continue;
          }
          std::cout << sensor_info_text(sensor.config.address, sensor.driver->model(), state);
        }
        std::cout.flush();
        co_return exit_code;
      });
}

}  // namespace tiltgate
