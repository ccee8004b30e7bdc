// A service that runs beside the gateway core, on its event loop: the HTTP status API and its
// history, the MQTT feed, the control socket. The composition root (app/) makes each one and
// attaches it to the Gateway, which starts, reloads and stops it with itself: a service sees
// every reload and the shutdown without the core knowing what it is.
#pragma once

#include <string_view>

#include "config/config.h"
#include "gateway/config_diff.h"

namespace tiltgate {

class GatewayService {
 public:
  virtual ~GatewayService() = default;
  // After the core is serving (buses open, Modbus listeners bound), still as the gateway was
  // started: only what may need its privileges (a port below 1024). A service whose table is
  // off does nothing; one that cannot start logs why: the PLC's Modbus service never depends
  // on it.
  virtual void start() = 0;
  // Then, once the gateway serves as its own user ([server] user, app/run_as_user.h): what
  // writes files (a store, the control socket), so that every file the gateway writes is that
  // user's and can be replaced by it at a reload.
  virtual void start_as_user() {}
  // The gateway serves `loaded` now; `diff` says what changed against the configuration
  // before. True when the service restarted (for the reload's summary line).
  virtual bool reload(const Config& loaded, const ConfigDiff& diff) = 0;
  // Before the buses stop.
  virtual void stop() = 0;
  // For the log: "http", "mqtt", "control socket".
  virtual std::string_view name() const = 0;
};

}  // namespace tiltgate
