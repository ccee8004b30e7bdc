#include "app/served_gateway.h"

#include <signal.h>
#include <unistd.h>

#include "app/audit_journal.h"
#include "app/journal_log.h"
#include "app/redundant_pair.h"
#include "monitoring/baseline_runner.h"
#include "mqtt/mqtt_payload.h"
#include "monitoring/record_download.h"
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
                               Gateway& gateway, MonitoringSource monitoring,
                               monitoring::MonitoringService& monitoring_service) {
  ConsoleContext context;
  context.monitoring = std::move(monitoring);
  // Used from requests only, after the service is made.
  context.baseline = [&monitoring_service](const std::string& request, const WriteOrigin& by) {
    return monitoring::answer_baseline(monitoring_service, request, by);
  };
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
            console_context(audit_, families, confirm_window_, gateway_, monitoring_source(),
                            monitoring_)),
      mqtt_(io.get_executor(), [this] { return status(SteadyClock::now()); }, config.mqtt,
            mqtt_events()),
      sparkplug_(io.get_executor(), gateway_, families, config.sparkplug,
                 [this] { return clock_.current(); }, burst_source()),
      control_(gateway_,
               monitoring::with_baselines(
                   with_capture(requested_command_runner(families, registered_family_commands())),
                   monitoring_)),
      monitoring_(gateway_, audit_) {
  redundancy_ = make_redundant_pair(io.get_executor(), config, families, gateway_);
  if (redundancy_) feed_while_active();
  gateway_.set_audit(audit_);
  gateway_.attach(control_);
  gateway_.attach(http_);
  // Before the feeds: their start asks the monitoring for the newest event.
  gateway_.attach(monitoring_);
  gateway_.attach(mqtt_);
  gateway_.attach(sparkplug_);
  // Each reading is flagged when the clock was not synchronised as it was taken.
  gateway_.check_clock_with([this] { return clock_.current().synchronised; });
}

MqttEventSource ServedGateway::mqtt_events() {
  // Called later, on the event loop: the service is made by then.
  MqttEventSource source;
  source.last = [this] { return monitoring_.last_event_seq(); };
  source.after = [this](std::uint64_t after) {
    std::vector<MqttEvent> events;
    for (const monitoring::EventRecord& e : monitoring_.events_after(after, 1000))
      events.push_back({e.seq, monitoring::event_json(e), e.unix_ms});
    return events;
  };
  // The bursts as the Sparkplug edge node takes them, made messages.
  const monitoring::BurstSource bursts = burst_source();
  source.last_burst = bursts.last;
  source.bursts_after = [after_of = bursts.after](std::uint64_t after) {
    std::vector<MqttBurst> messages;
    for (const monitoring::BurstBatch& b : after_of(after, 64))
      messages.push_back({b.seq, b.sensor, mqtt_burst_json(b), b.samples.back().unix_ms});
    return messages;
  };
  return source;
}

monitoring::BurstSource ServedGateway::burst_source() {
  // Called later, on the event loop: the service is made by then.
  monitoring::BurstSource source;
  source.last = [this] { return monitoring_.burst_feed().last(); };
  source.after = [this](std::uint64_t after, std::size_t max) {
    return monitoring_.burst_feed().after(after, max);
  };
  return source;
}

MonitoringSource ServedGateway::monitoring_source() {
  // Called later, from the HTTP threads: the service is made by then.
  MonitoringSource source;
  source.events = [this](const monitoring::EventQuery& query) {
    return monitoring_.events(query);
  };
  source.long_record_csv = [this](const std::string& sensor, std::int64_t from, std::int64_t to,
                                   std::size_t points)
      -> std::optional<Expected<std::string, std::string>> {
    if (!monitoring_.serves(sensor)) return std::nullopt;
    return monitoring::record_csv(monitoring_.record_of(sensor), from, to,
                                  monitoring::kMaxDownloadRows, points);
  };
  source.bursts = [this](const std::string& sensor) -> std::optional<std::filesystem::path> {
    if (!monitoring_.serves(sensor)) return std::nullopt;
    return monitoring_.bursts_of(sensor);
  };
  return source;
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
  status.clock = clock_.current();
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
