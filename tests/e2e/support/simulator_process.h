// `tiltgate sim ARGS --link DIR/tty` as a child process for the commissioning commands' tests,
// until destroyed (SIGTERM, then SIGKILL).
#pragma once

#include <doctest/doctest.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "e2e/support/gateway_process.h"

namespace tiltgate::test {

class SimulatorProcess {
 public:
  explicit SimulatorProcess(std::vector<std::string> args) {
    using namespace std::chrono_literals;
    std::filesystem::create_directory(dir_.path() / "sim");
    tty_ = (dir_.path() / "tty").string();
    args.insert(args.begin(), "sim");
    args.push_back("--link");
    args.push_back(tty_);
    process_ = std::make_unique<GatewayProcess>(args, dir_.path() / "sim");
    const auto deadline = std::chrono::steady_clock::now() + 15s;
    while (!std::filesystem::exists(tty_) && process_->running() &&
           std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(20ms);
    REQUIRE_MESSAGE(std::filesystem::exists(tty_), process_->log());
  }
  const std::string& tty() const { return tty_; }
  const TempDir& dir() const { return dir_; }

 private:
  TempDir dir_;
  std::string tty_;
  std::unique_ptr<GatewayProcess> process_;
};

}  // namespace tiltgate::test
