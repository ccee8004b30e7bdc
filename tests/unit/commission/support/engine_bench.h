// A commissioning engine's test bench: a simulated Rieker bus on a pseudo-terminal, opened as
// the command line opens it (commission/commission_bus.h), and the events an engine reports on
// it, kept in order. A test runs one engine coroutine and reads the events it reported.
#pragma once

#include <boost/asio/io_context.hpp>
#include <doctest/doctest.h>
#include <memory>
#include <optional>
#include <vector>

#include "commission/commission_bus.h"
#include "commission/commission_events.h"
#include "commission/commission_options.h"
#include "rieker/simulator.h"
#include "sim/support/run_coroutine.h"
#include "sim/support/termios2_skip.h"
#include "unit/support/scratch_dir.h"

namespace tiltgate::test {

// A sensor the simulator plays: an H6 with the serial and firmware the driver tests know.
inline rieker::SimulatedSensorOptions simulated_h6(std::uint16_t address, double x = 1.5,
                                                   double y = -2.25) {
  rieker::SimulatedSensorOptions s;
  s.address = address;
  s.serial = "962285";
  s.angle_x = x;
  s.angle_y = y;
  return s;
}

struct EngineBench {
  boost::asio::io_context io;
  ScratchDir dir{"tiltgate-engine"};
  std::optional<rieker::RiekerSimulator> sim;
  std::unique_ptr<CommissionBus> bus;
  std::vector<CommissionEvent> events;
  bool stopping = false;
  const EventSink report = [this](const CommissionEvent& event) { events.push_back(event); };

  // The simulator with `sensors`, and the bus as `--port TTY --protocol rieker --address
  // ADDRESSES...` opens it (no running gateway: the control socket is a path nobody serves).
  EngineBench(std::vector<rieker::SimulatedSensorOptions> sensors,
              std::vector<std::int64_t> addresses) {
    rieker::RiekerSimulatorOptions options;
    options.sensors = std::move(sensors);
    options.link_path = dir.path("ttyRS485");
    sim.emplace(io, std::move(options));
    const auto started = sim->start();
    REQUIRE_MESSAGE(started.has_value(), started.error());
    BusOptions bus_options;
    bus_options.port = sim->link_path();
    bus_options.protocol = "rieker";
    bus_options.addresses = std::move(addresses);
    bus_options.control_socket = dir.path("no-gateway.sock");
    const auto target = resolve_bus_options(bus_options, registered_families());
    REQUIRE_MESSAGE(target.has_value(), (target ? "" : target.error().front()));
    skip_unless_settable(target->bus.baud);  // a Rieker bus: 125000 baud needs termios2
    auto opened = CommissionBus::open(io.get_executor(), *target);
    REQUIRE_MESSAGE(opened.has_value(), (opened ? "" : opened.error().message));
    bus = std::move(*opened);
  }
  ~EngineBench() {
    bus.reset();
    sim->stop();
    run_for(io, std::chrono::milliseconds(10));
  }

  int run(boost::asio::awaitable<int> engine) { return run_coroutine(io, std::move(engine)); }

  // The events of one kind, in the order they were reported.
  template <class Event>
  std::vector<Event> all() const {
    std::vector<Event> found;
    for (const CommissionEvent& event : events)
      if (const auto* e = std::get_if<Event>(&event)) found.push_back(*e);
    return found;
  }
};

}  // namespace tiltgate::test
