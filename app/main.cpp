// tiltgate: Modbus/TCP gateway for RS485 inclinometers.
#include <CLI/CLI.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <string>
#include <vector>

#include "app/audit_command.h"
#include "accounts/user_command.h"
#include "app/config_commands.h"
#include "app/demo_commands.h"
#include "app/journal_log.h"
#include "capture_cli/capture_command.h"
#include "monitoring_cli/baseline_command.h"
#include "monitoring_cli/bursts_command.h"
#include "monitoring_cli/history_command.h"
#include "commission_cli/commands.h"

namespace {

void set_up_logging(const std::string& level) {
  auto logger = spdlog::stderr_color_mt("tiltgate");
  spdlog::set_default_logger(logger);
  // Under systemd, stderr is the journal: it keeps the time, and takes the priority from a
  // "<4>" prefix (journal_log.h).
  if (tiltgate::stderr_is_journal())
    spdlog::set_formatter(tiltgate::journal_formatter());
  else
    spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %^%-5l%$ %v");
  spdlog::set_level(spdlog::level::from_str(level));
}

// "A, B and C": the families' titles.
std::string family_titles(tiltgate::FamilyCommandsList families) {
  std::string titles;
  for (std::size_t i = 0; i < families.size(); ++i) {
    if (i > 0) titles += i + 1 == families.size() ? " and " : ", ";
    titles += families[i]->title;
  }
  return titles;
}

}  // namespace

int main(int argc, char** argv) {
  // The sensor families this build serves: asked for here, once, and handed to every command;
  // what the gateway runs of them, and what the command line shows and runs.
  const tiltgate::FamilyList families = tiltgate::registered_families();
  const tiltgate::FamilyCommandsList commands = tiltgate::registered_family_commands();
  CLI::App app{"tiltgate: Modbus/TCP gateway for " + family_titles(commands) + " inclinometers"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("tiltgate ") + TILTGATE_VERSION);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error, critical or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "critical", "off"}))
      ->capture_default_str();

  // One add_<command>() per command file; each keeps its options and knows how to run.
  const std::vector<tiltgate::Subcommand> subcommands = {
      tiltgate::add_run(app, families),
      tiltgate::add_check(app, families),
      tiltgate::add_map(app, families),
      tiltgate::add_demo(app, commands),
      // Commissioning: the vendor's Windows apps, from an SSH session.
      tiltgate::add_info(app, families, commands),
      tiltgate::add_watch(app, families, commands),
      tiltgate::add_scan(app, families, commands),
      tiltgate::add_set(app, families, commands),
      tiltgate::add_raw(app, families, commands),
      tiltgate::add_sim(app, commands),
      // Diagnostics: what a line carries, for Wireshark.
      tiltgate::add_capture(app, families),
      // Monitoring: a sensor's baseline, its long record, its bursts.
      tiltgate::add_baseline(app, families),
      tiltgate::add_history(app, families),
      tiltgate::add_bursts(app, families),
      tiltgate::add_audit(app),
      tiltgate::add_user(app),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every other parse error is a usage error, exit 2.
    return app.exit(e) == 0 ? 0 : 2;
  }
  for (const tiltgate::Subcommand& subcommand : subcommands) {
    if (!*subcommand.cli) continue;
    if (subcommand.quiet && app.get_option("--log-level")->count() == 0) log_level = "error";
    set_up_logging(log_level);
    return subcommand.run();
  }
  return 2;
}
