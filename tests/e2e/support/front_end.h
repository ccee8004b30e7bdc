// The front end the commissioning commands' end-to-end tests drive (tests/CMakeLists.txt
// registers those tests twice): the command on its own line, as it runs at a bare tty, or, with
// TILTGATE_E2E_FRONT_END=gateway ("e2e via gateway:"), the same command through a running
// gateway that serves its bus (docs/commissioning.md, "Every commissioning test through a
// running gateway"). The tests' assertions are the same for both.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "e2e/support/gateway_process.h"

namespace tiltgate::test {

// Whether this run's commands go through a running gateway.
bool through_gateway();

// Through a running gateway, prints "skipped through a running gateway: REASON" (which ctest's
// SKIP_REGULAR_EXPRESSION counts as skipped) and returns true: the test then returns at once.
// Used where a test cannot hold through a gateway by design, or, with a "BUG: " reason, where it
// fails in a way that is the product's to fix.
bool skipped_through_gateway(std::string_view reason);

// `tiltgate run` serving the one bus a commissioning command names (its --port with the line
// options, or the [[bus]] of its --config that --bus or --sensor names), its control socket in
// a folder of its own; stopped when destroyed. Does nothing for a command that names no bus.
class ServingGateway {
 public:
  explicit ServingGateway(const std::vector<std::string>& command);
  ~ServingGateway();
  ServingGateway(const ServingGateway&) = delete;
  ServingGateway& operator=(const ServingGateway&) = delete;

  // The command with --via-gateway and this gateway's --control-socket (in place of one it
  // gave); as it stands when no gateway was started.
  std::vector<std::string> through(std::vector<std::string> command) const;

 private:
  TempDir dir_;
  std::string socket_;
  std::unique_ptr<GatewayProcess> process_;
};

// Runs a commissioning command (`scan`, `info`, `watch`, `set`, `raw`) to completion through
// the selected front end. Through a gateway, the two lines a command adds there on stderr
// ("through the running gateway: ...", "note: the gateway runs ...") are taken out, after
// checking that every command that was not refused as a usage error (exit 2) went through it.
CommandResult run_command(std::vector<std::string> args);

// A commissioning command left running (`watch` until SIGTERM), through the selected front end.
class CommandProcess {
 public:
  CommandProcess(std::vector<std::string> args, const std::filesystem::path& log_dir);
  std::string output() const { return process_.output(); }
  std::string log() const { return process_.log(); }
  bool running() { return process_.running(); }
  int terminate() { return process_.terminate(); }

 private:
  ServingGateway gateway_;  // first made, last stopped: it outlives the command
  GatewayProcess process_;
};

}  // namespace tiltgate::test
