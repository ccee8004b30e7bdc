#include "app/served_gateway.h"

#include <signal.h>
#include <unistd.h>

#include "app/audit_journal.h"
#include "app/journal_log.h"
#include "app/redundant_pair.h"
#include "commission_wire/requested_command.h"
#include "control/capture_runner.h"
#include "driver/family_commands.h"

namespace tiltgate {

namespace {

// What the web console reaches besides the gateway (console/console_handler.h): the trail its
// changes are recorded in, the families a configuration is checked with, a reload as
// `systemctl reload` asks for one (SIGHUP, app/config_commands.cpp), so an applied file is
// taken up exactly as an edited one is, and the window an applied file awaits confirmation in.
void reload_by_hangup() { ::kill(::getpid(), SIGHUP); }

ConsoleContext console_context(AuditTrail& audit, FamilyList families, ConfirmWindow& window,
                               Gateway& gateway) {
  ConsoleContext context;
  context.reset_counters = [&gateway](CounterScope scope, std::string_view name) {
    return scope == CounterScope::bus ? gateway.reset_bus_counters(name)
                                      : gateway.reset_sensor_counters(name);
  };
  context.audit = &audit;
  context.families = families;
  context.commands = registered_family_commands();
  context.reload = reload_by_hangup;
  context.confirm_window = &window;
  return context;
}

// The trail's options from [audit], and its journal entries when stderr is the journal's
// stream: each record with its fields and chain hash (app/audit_journal.h).
AuditOptions audit_options(const AuditConfig& config) {
  AuditOptions options;
  options.memory_budget_bytes = std::uint64_t(config.memory_kib) * 1024;
  options.when_full = config.when_full == AuditConfig::WhenFull::refuse ? AuditWhenFull::refuse
                                                                         : AuditWhenFull::keep;
  if (stderr_is_journal()) options.journal = send_audit_to_journal;
  return options;
}

}  // namespace

ServedGateway::ServedGateway(boost::asio::io_context& io, const Config& config,
                             FamilyList families)
    : confirm_window_(config.path, &audit_, reload_by_hangup),
      gateway_(io, config, families),
      http_(gateway_, [this] { return status(SteadyClock::now()); },
            console_context(audit_, families, confirm_window_, gateway_)),
      mqtt_(io.get_executor(), [this] { return status(SteadyClock::now()); }, config.mqtt),
      sparkplug_(io.get_executor(), gateway_, families, config.sparkplug),
      control_(gateway_,
               with_capture(requested_command_runner(families, registered_family_commands()))) {
  redundancy_ = make_redundant_pair(io.get_executor(), config, families, gateway_);
  if (redundancy_) feed_while_active();
  gateway_.set_audit(audit_);
  gateway_.attach(control_);
  gateway_.attach(http_);
  gateway_.attach(mqtt_);
  gateway_.attach(sparkplug_);
}

void ServedGateway::feed_while_active() {
  // A host must see one source of live data, never two Sparkplug edge nodes of one id: every
  // gateway of a pair starts as the standby, so neither feed starts with the gateway. The
  // controller's first word comes on the event loop, which runs only after start_as_user().
  mqtt_.pause();
  sparkplug_.pause();
  redundancy_->on_role_change([this](bool active) {
    if (active) {
      mqtt_.resume();
      sparkplug_.resume();
    } else {
      mqtt_.pause();
      sparkplug_.pause();
    }
  });
}

void ServedGateway::start_as_user() {
  audit_.open(gateway_.config().server.state_dir, audit_options(gateway_.config().audit));
  gateway_.start_as_user();
}

GatewayStatus ServedGateway::status(SteadyClock::time_point now) const {
  GatewayStatus status = gateway_.status(now);
  status.http_connections_denied = http_.connections_denied();
  status.http_clients_closed = http_.clients_closed();
  status.http_rates = http_.request_rates();
  status.console = http_.console_counts();
  status.mqtt = mqtt_.stats();
  if (status.mqtt) status.stores.push_back(status.mqtt->store);
  status.sparkplug = sparkplug_.stats();
  if (auto store = sparkplug_.store_stats()) status.stores.push_back(*store);
  if (redundancy_) status.redundancy = redundancy_->status();
  return status;
}

}  // namespace tiltgate
