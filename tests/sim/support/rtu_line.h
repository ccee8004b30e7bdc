// A Modbus RTU bus with one simulated inclinometer at slave 1 on a pseudo-terminal, and a
// SerialLine to it (19200 baud 8E1, no retries), for tests that look at what the line does with
// one exchange: its trace log, its frame recorder.
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <doctest/doctest.h>
#include <optional>

#include "modbus_rtu/reply_framer.h"
#include "modbus_rtu/simulator/inclinometer_preset.h"
#include "modbus_rtu/simulator/simulator.h"
#include "serial/serial_line.h"
#include "sim/support/run_coroutine.h"

namespace tiltgate::test {

struct RtuLine {
  boost::asio::io_context io;
  std::optional<modbus_rtu::RtuSimulator> sim;
  std::optional<SerialLine> line;

  // `timeout`: generous, so that only a corrupted reply waits it out.
  explicit RtuLine(std::chrono::milliseconds timeout = std::chrono::milliseconds(500)) {
    modbus_rtu::RtuSimulatorOptions options;
    options.devices.push_back(modbus_rtu::rtu_inclinometer(1));
    sim.emplace(io, std::move(options));
    REQUIRE(sim->start().has_value());
    SerialLineOptions line_options;
    line_options.name = "rtu1";
    line_options.port = sim->slave_path();
    line_options.baud = 19200;
    line_options.framing = Framing::eight_even_one;
    line_options.timeout = timeout;
    line_options.retries = 0;
    line_options.late_guard = std::chrono::milliseconds(50);
    line.emplace(io.get_executor(), line_options);
    REQUIRE(line->start());
  }
  ~RtuLine() {
    line->stop();
    sim->stop();
  }

  // Reads holding register 0 of slave 1 (the filter level, 4 by default).
  Expected<Done, LineError> read_filter() {
    const auto request = modbus_rtu::read_request(1, modbus_rtu::RegisterBank::holding, 0, 1);
    REQUIRE(request.has_value());
    modbus_rtu::RtuReplyFramer framer(*request);
    LineRequest line_request;
    line_request.bytes = request->frame;
    line_request.framer = &framer;
    return run_coroutine(io, line->transact(std::move(line_request)));
  }
};

}  // namespace tiltgate::test
