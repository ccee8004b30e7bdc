#include "app/config_reload.h"

#include <spdlog/spdlog.h>

#include "config/config_loader.h"
#include "config/machine_checks.h"
#include "config/reload_checks.h"
#include "driver/visible_text.h"

namespace tiltgate {

namespace {

// SIGHUP: the file again, through the loader `check` uses. A valid file is applied to the
// running gateway; an invalid one is refused with every error logged, as `check` prints them.
void reload_or_refuse(Gateway& gateway, const std::string& config_path, FamilyList families) {
  spdlog::info("SIGHUP: reloading {}", visible_text(config_path));
  // A start-only table ([redundancy]) that the file changes refuses the reload.
  auto loaded = checked_for_reload(
      gateway.config(), checked_on_this_machine(load_config_file(config_path, families)));
  if (!loaded) {
    for (const ConfigError& error : loaded.error())
      spdlog::error("{}", visible_text(error.to_string()));
    spdlog::error("reload refused: {} error(s); still serving the configuration loaded at {}",
                  loaded.error().size(), gateway.loaded_at());
    return;
  }
  gateway.reload(*loaded);
}

}  // namespace

// systemd shows the service as reloading from RELOADING=1 until READY=1, which comes whether
// the file was applied or refused: either way the gateway serves again.
void reload_on_sighup(boost::asio::signal_set& hangups, Gateway& gateway,
                      const std::string& config_path, FamilyList families,
                      ServiceNotifier& notifier) {
  hangups.async_wait([&hangups, &gateway, &config_path, families, &notifier](
                         const boost::system::error_code& ec, int) {
    if (ec) return;
    notifier.reloading();
    reload_or_refuse(gateway, config_path, families);
    notifier.ready();
    reload_on_sighup(hangups, gateway, config_path, families, notifier);
  });
}

}  // namespace tiltgate
