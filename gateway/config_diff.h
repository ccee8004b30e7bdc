// What a reload changes (SIGHUP, Gateway::reload in gateway/gateway.cpp): the running configuration and the
// file's new one, compared by name. Pure: the gateway applies the result.
//
// A bus is kept when its settings are the same; otherwise it is reopened (same name), added or
// removed. A sensor is kept only when its settings are the same AND its bus is kept (its driver
// was made for that bus's protocol and timing); otherwise it is changed (same name, so the same
// sensor moved to another bus or with a new map, poll, unit id, ...), added or removed. A
// renamed sensor or bus is a removed one plus an added one. Where a setting was declared (the
// `line` fields) is not a setting, nor is a bus's tcp_port (which listener serves its units:
// the gateway routes every unit anew at each reload). Aggregates are always rebuilt.
#pragma once

#include <string>
#include <vector>

#include "config/config.h"

namespace tiltgate {

struct ConfigDiff {
  // Names, in the order of the file they come from (removed ones: the old file's).
  std::vector<std::string> buses_kept, buses_reopened, buses_added, buses_removed;
  std::vector<std::string> sensors_kept, sensors_changed, sensors_added, sensors_removed;
  bool server_changed = false;          // any [server] key
  bool server_listener_changed = false; // listen or port: the Modbus listener is rebound
  bool control_socket_changed = false;  // [server] control_socket
  bool http_changed = false;
  bool mqtt_changed = false;
  bool sparkplug_changed = false;

  // No bus reopened, added or removed.
  bool buses_unchanged() const {
    return buses_reopened.empty() && buses_added.empty() && buses_removed.empty();
  }
  // No sensor changed, added or removed.
  bool sensors_unchanged() const {
    return sensors_changed.empty() && sensors_added.empty() && sensors_removed.empty();
  }
};

// The same settings, wherever in the file they were declared.
bool same_settings(const BusConfig& a, const BusConfig& b);
bool same_settings(const SensorConfig& a, const SensorConfig& b);

ConfigDiff diff_configs(const Config& running, const Config& loaded);

// One line for the log: "buses kept: a; reopened: b; ... sensors kept: x; changed: y; ...",
// "-" for an empty list.
std::string summarize(const ConfigDiff& diff);

// What an applied file changes, for the audit trail: summarize()'s line, then the sections
// changed ("sections changed: server, http" or "-"), then each door's address that moved
// ("[http] 127.0.0.1:8080 -> 0.0.0.0:8081"). Names and addresses only: never a password.
std::string describe_changes(const Config& running, const Config& loaded);

}  // namespace tiltgate
