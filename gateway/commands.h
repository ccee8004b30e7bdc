// The subcommands of the tiltgate executable. Each returns the process exit code.
#pragma once

#include <cstdint>
#include <string>

namespace tiltgate {

int check_command(const std::string& config_path);
int map_command(const std::string& config_path, const std::string& format);
int run_command(const std::string& config_path);

struct DemoOptions {
  std::string listen = "127.0.0.1";
  std::uint16_t port = 1502;
};
int demo_command(const DemoOptions& options);

struct RiekerSimOptions {
  std::string sensors = "h6:223";  // model:address[,model:address...]
  std::string link;                // optional stable symlink to the pty
  std::uint32_t pace_baud = 0;     // 0: answer at once; else pace replies at this baud rate
};
int sim_rieker_command(const RiekerSimOptions& options);

struct SpectronSimOptions {
  std::string protocol = "9bit";   // "9bit" (9-bit addressing) or "modbus" (Modbus-ASCII)
  std::string sensors = "dyna:1";  // dyna:address[,dyna:address...]
  std::string link;                // optional stable symlink to the pty
  std::uint32_t pace_baud = 0;     // 0: answer at once; else pace replies at this baud rate
};
int sim_spectron_command(const SpectronSimOptions& options);

}  // namespace tiltgate
