// `tiltgate baseline` through the control socket (monitoring_cli/baseline_command.h): a `run`
// whose request is a baseline's is answered by the monitoring (set_baseline()), not by the
// commissioning engine, and never touches the line.
//
//   {"command": "baseline", "sensor": "mast", "set": "current"}         the last reading
//   {"command": "baseline", "sensor": "mast", "set": "value", "x": 0.1, "y": -0.2}
//   {"command": "baseline", "sensor": "mast", "set": "clear"}           the configuration's again
//   {"command": "baseline", "sensor": "mast", "set": "show"}            only says what it is
//
// Events: one {"event": "baseline", "sensor", "x", "y", "stored": true|false, "by", "unix_ms"}
// (stored: set since the configuration, with who and when), then exit 0; or {"event": "error",
// "message"} and exit 1 (2 for a request that makes no sense). Each change is recorded in the
// audit trail as the session's door and person. The web console asks the same requests
// (console/console_baseline_routes.cpp) through answer_baseline().
#pragma once

#include <string>

#include "control/command_runner.h"
#include "monitoring/baseline_answer.h"
#include "monitoring/monitoring_service.h"

namespace tiltgate::monitoring {

bool is_baseline_request(const std::string& request);

// One baseline request answered, on the gateway's executor.
BaselineAnswer answer_baseline(MonitoringService& monitoring, const std::string& request,
                               const WriteOrigin& by);

// A runner that answers baseline requests itself and hands every other one to `next`.
CommandRunner with_baselines(CommandRunner next, MonitoringService& monitoring);

}  // namespace tiltgate::monitoring
