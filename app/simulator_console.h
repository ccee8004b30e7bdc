// `tiltgate sim FAMILY`'s standard input while it runs: one command a line for the simulator
// (BusSimulator::command, e.g. "angle 223 12.5 -3.25"), answered on standard output with "ok"
// or "error: WHY", one line each, so a script or a benchmark can change a simulated sensor and
// know when it took effect. Read only from a pipe or a socket: a terminal is left alone (a
// simulator started in the background of an interactive shell would be stopped by SIGTTIN),
// and a file or /dev/null has no commands to wait for.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <functional>
#include <optional>
#include <string>

#include "driver/bus_simulator.h"

namespace tiltgate {

class SimulatorConsole {
 public:
  // Reads `input` (a file descriptor, duplicated: the caller keeps its own) and writes the
  // answers through `answer`.
  SimulatorConsole(boost::asio::io_context& io, BusSimulator& simulator, int input,
                   std::function<void(const std::string&)> answer);
  // Starts reading when `input` is a pipe or a socket; false when it is not (nothing is read).
  bool start();
  // Stops reading (at shutdown), so the pending read ends with the loop.
  void stop();

 private:
  boost::asio::awaitable<void> read_lines();

  boost::asio::io_context& io_;
  BusSimulator& simulator_;
  int input_;
  std::function<void(const std::string&)> answer_;
  std::optional<boost::asio::posix::stream_descriptor> stream_;
};

}  // namespace tiltgate
