// The control socket ([server] control_socket, control/control_server.h) as a service attached
// to the gateway (gateway/gateway_service.h): it runs commissioning commands on the
// gateway's buses, so a reload that changes the socket's path or the buses restarts it with
// the buses served then (a command in progress is ended and reconnects); a socket that could
// not be had is tried again at every reload.
#pragma once

#include <memory>

#include "control/control_server.h"
#include "gateway/gateway.h"
#include "gateway/gateway_service.h"
#include "gateway/retired.h"
#include "gateway/start_retry.h"

namespace tiltgate {

class ControlService final : public GatewayService {
 public:
  // `runner`: what a command's `run` does on its bus (control/command_runner.h).
  ControlService(const Gateway& gateway, CommandRunner runner);
  ~ControlService() override;

  // Nothing before the switch to [server] user: the socket file is made as that user, so it
  // can remove and make it again at a reload.
  void start() override {}
  void start_as_user() override;
  bool reload(const Config& loaded, const ConfigDiff& diff) override;
  void stop() override;
  std::string_view name() const override { return "control socket"; }

 private:
  // A server for the gateway's buses now, when [server] control_socket is set.
  void make_server();
  // The server that could not start, tried again (StartRetry): true once it listens.
  bool start_again();

  const Gateway& gateway_;
  CommandRunner runner_;
  std::unique_ptr<ControlServer> server_;
  // Servers a reload replaced, freed once their sessions have ended.
  Retired<ControlServer> retired_;
  StartRetry retry_;  // while the server could not start
};

}  // namespace tiltgate
