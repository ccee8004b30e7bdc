// The lines a running simulator takes on its standard input (BusSimulator::command): a verb,
// the bus address of the simulated sensor it changes, and numbers, separated by blanks:
// "angle 223 12.5 -3.25".
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "driver/expected.h"

namespace tiltgate {

struct SimulatorCommand {
  std::string verb;
  std::uint32_t address = 0;
  std::vector<double> values;
};

// The line's verb, address and numbers; the error names the word that is not one. An empty
// line (or one of blanks) is an error too.
Expected<SimulatorCommand, std::string> parse_simulator_command(std::string_view line);

}  // namespace tiltgate
