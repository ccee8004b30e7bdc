#include "control/control_service.h"

#include <spdlog/spdlog.h>

#include "driver/visible_text.h"

namespace tiltgate {

ControlService::ControlService(const Gateway& gateway, CommandRunner runner)
    : gateway_(gateway),
      runner_(std::move(runner)),
      retired_(gateway.executor()),
      retry_(gateway.executor()) {
  make_server();
}

ControlService::~ControlService() = default;

void ControlService::make_server() {
  const Config& config = gateway_.config();
  if (config.server.control_socket.empty()) return;
  server_ = std::make_unique<ControlServer>(gateway_.executor(), config.server.control_socket,
                                            served_buses(gateway_), runner_);
}

void ControlService::start_as_user() {
  retry_.cancel();
  if (!server_) return;
  if (auto started = server_->start(); !started) {
    spdlog::warn("control socket off: {}; commissioning commands cannot use this gateway's "
                 "buses; tried again every {} s",
                 started.error(), StartRetry::kInterval.count());
    retry_.schedule([this] { return start_again(); });
    return;
  }
  spdlog::info("control socket {}", visible_text(server_->path()));
}

bool ControlService::start_again() {
  if (!server_) return true;
  if (auto started = server_->start(); !started) {
    spdlog::debug("control socket still off: {}", started.error());
    return false;
  }
  spdlog::info("control socket {}", visible_text(server_->path()));
  return true;
}

bool ControlService::reload(const Config& loaded, const ConfigDiff& diff) {
  if (!server_ && loaded.server.control_socket.empty()) return false;
  // Its sessions hold the old buses. One that is off (its folder was not writable) is tried
  // again, so fixing the folder needs no restart.
  const bool off = server_ && !server_->listening();
  if (!off && !diff.control_socket_changed && diff.buses_unchanged()) return false;
  if (server_) {
    server_->stop();
    retired_.add(std::move(server_));
  }
  make_server();
  start_as_user();
  return true;
}

void ControlService::stop() {
  retry_.cancel();
  if (server_) server_->stop();
}

}  // namespace tiltgate
