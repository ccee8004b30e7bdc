// The gateway as `tiltgate run` and `tiltgate demo` serve it: the core (gateway/gateway.h) and
// every service beside it, made here and attached to it: the HTTP status API and its history,
// the MQTT feed, the Sparkplug B edge node and the control socket, each on or off as its configuration says. The one
// place that knows every service.
#pragma once

#include <boost/asio/io_context.hpp>

#include "audit/audit_trail.h"
#include "clock/clock_watch.h"
#include "config/config.h"
#include "control/control_service.h"
#include "gateway/gateway.h"
#include "monitoring/monitoring_service.h"
#include "redundancy/redundancy_controller.h"
#include "mqtt/mqtt_service.h"
#include "sparkplug/sparkplug_service.h"
#include "console/confirm_window.h"
#include "console/http_service.h"

namespace tiltgate {

class ServedGateway {
 public:
  ServedGateway(boost::asio::io_context& io, const Config& config, FamilyList families);

  Gateway& gateway() { return gateway_; }
  AuditTrail& audit() { return audit_; }
  // The system clock's state, for whoever stamps or flags readings by it.
  const ClockWatch& clock() const { return clock_; }
  // Once the gateway serves as its own user (or at once for the demo): the audit trail opens
  // its folder under [server] state_dir (in memory until then, and for good without one), so
  // its files are that user's; then the services' start_as_user().
  void start_as_user();
  const Gateway& gateway() const { return gateway_; }
  // Events, baselines and the long record (monitoring/monitoring_service.h).
  monitoring::MonitoringService& monitoring() { return monitoring_; }
  // Where a configuration applied through the console awaits its confirmation.
  ConfirmWindow& confirm_window() { return confirm_window_; }
  // The status the API, the metrics, the history and the MQTT feed show: the core's, with the
  // services' own counters.
  GatewayStatus status(SteadyClock::time_point now) const;

 private:
  // With [redundancy]: the MQTT feed and the Sparkplug edge node run only while this gateway
  // is the active one of its pair.
  void feed_while_active();
  // What the HTTP API reads of the monitoring (events, the long record), on its threads.
  MonitoringSource monitoring_source();
  // The monitoring's events for the MQTT feed's <prefix>/events.
  MqttEventSource mqtt_events();
  monitoring::BurstSource burst_source();

  // Before the gateway: the buses' writes and the services record into it until they stop.
  // So it goes last, and its destructor writes every record still queued for its writer
  // thread before the process exits (AuditTrail::close).
  AuditTrail audit_{""};
  // Before the gateway and the services, which ask it (from any thread) until they stop.
  ClockWatch clock_;
  // Before the console, which applies through it; after the trail, which it records in.
  ConfirmWindow confirm_window_;
  // With [redundancy]: who keeps the lines (app/redundant_pair.h), made once the gateway is;
  // goes after it, whose stop() stops it.
  std::unique_ptr<RedundancyController> redundancy_;
  Gateway gateway_;  // first: the services refer to it, and go before it
  HttpService http_;
  MqttService mqtt_;
  SparkplugService sparkplug_;
  ControlService control_;
  monitoring::MonitoringService monitoring_;
};

}  // namespace tiltgate
