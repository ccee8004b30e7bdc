// Starts build/tiltgate as a child process for end-to-end tests, and the helpers around it:
// a free loopback port, a temporary directory with a config file, the child's stderr.
#pragma once

#include <chrono>
#include <filesystem>
#include <string>
#include <sys/types.h>
#include <vector>

namespace tiltgate::test {

// A port nothing listens on right now (bind to 0, read it, close).
std::uint16_t free_tcp_port();

class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path write(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path path_;
};

class GatewayProcess {
 public:
  // Runs TILTGATE_BINARY with `args`; stderr and stdout go to files in `log_dir`.
  GatewayProcess(std::vector<std::string> args, const std::filesystem::path& log_dir);
  ~GatewayProcess();  // SIGTERM, then SIGKILL if it does not exit within 5 s

  // Waits until a TCP connect to 127.0.0.1:port succeeds; false on time-out or early exit.
  bool wait_listening(std::uint16_t port, std::chrono::seconds limit = std::chrono::seconds(15));
  // Sends SIGTERM and waits for the exit code (-1 on time-out; 128+N if killed by signal N).
  int terminate(std::chrono::seconds limit = std::chrono::seconds(10));
  // Sends `signal` (SIGHUP: reload); false when the process is gone.
  bool signal(int signal);
  // Waits for the process to exit by itself.
  int wait_exit(std::chrono::seconds limit = std::chrono::seconds(10));
  std::string log() const;  // stderr so far
  std::string output() const;  // stdout so far
  bool running();

 private:
  pid_t pid_ = -1;
  int exit_code_ = -1;
  std::filesystem::path stderr_path_;
  std::filesystem::path stdout_path_;
};

// Runs TILTGATE_BINARY to completion (for check/map): exit code, stdout and stderr.
struct CommandResult {
  int exit_code;
  std::string out;
  std::string err;
};
CommandResult run_tiltgate(std::vector<std::string> args);

}  // namespace tiltgate::test
