// SIGHUP reloads the configuration file (`systemctl reload tiltgate`, and a console apply,
// which sends it): the file again, through the loader `check` uses, applied to the running
// gateway when valid and refused, every error logged, when not. `tiltgate run` and `tiltgate
// demo` (which serves a file of its own) both reload so.
#pragma once

#include <boost/asio/signal_set.hpp>
#include <string>

#include "app/service_notify.h"
#include "driver/family.h"
#include "gateway/gateway.h"

namespace tiltgate {

// Waits for SIGHUP on `hangups`, reloads `config_path` into `gateway`, and waits again, until
// `hangups` is cancelled. Each argument must outlive the wait.
void reload_on_sighup(boost::asio::signal_set& hangups, Gateway& gateway,
                      const std::string& config_path, FamilyList families,
                      ServiceNotifier& notifier);

}  // namespace tiltgate
