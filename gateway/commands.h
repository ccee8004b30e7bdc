// The subcommands of the tiltgate executable. Each returns the process exit code.
#pragma once

#include <cstdint>
#include <string>

#include "driver/family.h"

namespace tiltgate {

int check_command(const std::string& config_path);
int map_command(const std::string& config_path, const std::string& format);
int run_command(const std::string& config_path);

struct DemoOptions {
  std::string listen = "127.0.0.1";
  std::uint16_t port = 1502;
};
int demo_command(const DemoOptions& options);

// `tiltgate sim FAMILY`: the family's simulator on a pseudo-terminal until SIGINT/SIGTERM.
int sim_command(const FamilyDescriptor& family, const SimulatorSetup& setup);

}  // namespace tiltgate
