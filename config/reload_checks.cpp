#include "config/reload_checks.h"

#include <fmt/format.h>

#include <string>
#include <vector>

namespace tiltgate {

namespace {

std::string_view role_written(RedundancyConfig::Role role) {
  switch (role) {
    case RedundancyConfig::Role::primary:
      return "primary";
    case RedundancyConfig::Role::standby:
      return "standby";
    case RedundancyConfig::Role::none:
      break;
  }
  return "none";
}

// As written in the file: "HOST:PORT", an IPv6 address in brackets.
std::string peer_written(const RedundancyConfig& redundancy) {
  if (redundancy.peer_host.find(':') != std::string::npos)
    return fmt::format("[{}]:{}", redundancy.peer_host, redundancy.peer_port);
  return fmt::format("{}:{}", redundancy.peer_host, redundancy.peer_port);
}

// "role \"primary\" -> \"standby\", takeover_ms 2000 -> 3000": each key that differs.
std::string redundancy_changes(const RedundancyConfig& was, const RedundancyConfig& is) {
  if (!was.enabled()) return fmt::format("adds it (role \"{}\")", role_written(is.role));
  if (!is.enabled()) return fmt::format("removes it (running as \"{}\")", role_written(was.role));
  std::vector<std::string> changes;
  if (was.role != is.role)
    changes.push_back(
        fmt::format("role \"{}\" -> \"{}\"", role_written(was.role), role_written(is.role)));
  if (peer_written(was) != peer_written(is))
    changes.push_back(fmt::format("peer \"{}\" -> \"{}\"", peer_written(was), peer_written(is)));
  if (was.takeover != is.takeover)
    changes.push_back(
        fmt::format("takeover_ms {} -> {}", was.takeover.count(), is.takeover.count()));
  if (was.failback != is.failback)
    changes.push_back(fmt::format("failback {} -> {}", was.failback, is.failback));
  return fmt::format("changes it ({})", fmt::join(changes, ", "));
}

}  // namespace

ConfigErrors check_reload(const Config& running, const Config& loaded) {
  ConfigErrors errors;
  if (!(running.redundancy == loaded.redundancy))
    errors.push_back(FileError{
        loaded.path, 0, 0, "redundancy",
        fmt::format("[redundancy] is read only at start, and this file {}: a reload cannot "
                    "apply it. Restart the gateway to serve this file (systemctl restart "
                    "tiltgate), or put [redundancy] back as it runs to reload the rest",
                    redundancy_changes(running.redundancy, loaded.redundancy))});
  return errors;
}

Expected<Config, ConfigErrors> checked_for_reload(const Config& running,
                                                  Expected<Config, ConfigErrors> loaded) {
  if (!loaded) return loaded;
  ConfigErrors errors = check_reload(running, *loaded);
  if (!errors.empty()) return Unexpected{std::move(errors)};
  return loaded;
}

}  // namespace tiltgate
