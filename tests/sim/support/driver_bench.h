// A driver test bench: a simulator on a pseudo-terminal behind a stable link, a real
// SerialLine opened on that link, and helpers that run a driver's coroutines to completion.
// Shared by the sensor families' driver tests; each supplies its simulator and line options.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <functional>
#include <doctest/doctest.h>
#include <memory>
#include <optional>

#include "driver/adaptive_reply_timeout.h"
#include "driver/sensor_driver.h"
#include "serial/serial_line.h"
#include "sim/support/raw_tty_client.h"
#include "sim/support/run_coroutine.h"
#include "sim/support/termios2_skip.h"
#include "unit/support/scratch_dir.h"

namespace tiltgate::test {

// The reply time-outs drivers under test get: generous, since the machine may be busy.
inline constexpr ReplyTimeouts kBenchReplyTimeouts{std::chrono::milliseconds(100),
                                                   std::chrono::milliseconds(1000)};

template <class Simulator>
struct DriverBench {
  boost::asio::io_context io;
  ScratchDir dir{"tiltgate-driver"};
  std::optional<Simulator> sim;
  std::unique_ptr<SerialLine> line;

  // Starts the simulator at dir/ttyRS485 and a line on it. The line's port, time-out, late
  // guard and reopen back-off are set here; `line_options` brings the rest (framing, baud,
  // retries), and `adjust` may change any of them last.
  template <class SimulatorOptions>
  DriverBench(SimulatorOptions sim_options, SerialLineOptions line_options,
              const std::function<void(SerialLineOptions&)>& adjust = {}) {
    sim_options.link_path = dir.path("ttyRS485");
    sim.emplace(io, std::move(sim_options));
    const auto started = sim->start();
    REQUIRE_MESSAGE(started.has_value(), started.error());
    line_options.port = sim->link_path();
    line_options.timeout = kBenchReplyTimeouts.base;
    line_options.late_guard = std::chrono::milliseconds(100);
    line_options.reopen_min = std::chrono::milliseconds(20);
    line_options.reopen_max = std::chrono::milliseconds(100);
    if (adjust) adjust(line_options);
    skip_unless_settable(line_options);
    line = std::make_unique<SerialLine>(io.get_executor(), line_options);
    REQUIRE(line->start());
  }
  ~DriverBench() {
    line->stop();
    sim->stop();
    run_for(io, std::chrono::milliseconds(10));
  }

  void poll(SensorDriver& driver) { run_coroutine(io, driver.poll(*line)); }
  WriteResult write(SensorDriver& driver, WriteTarget target, double value) {
    return run_coroutine(io, driver.write(*line, target, value));
  }
  // Lets the line's back-off timer reopen the port; true once it has (a new generation).
  bool wait_for_reopen(std::uint64_t generation) {
    for (int i = 0; i < 100 && line->generation() == generation; ++i) {
      run_for(io, std::chrono::milliseconds(20));
    }
    return line->generation() > generation;
  }
};

}  // namespace tiltgate::test
