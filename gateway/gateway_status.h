// What the HTTP status API and the metrics show of a running gateway: a copy of each sensor's
// and each bus's state taken at one moment, as plain values, so the text built from it
// (status/status_json.h, status/status_metrics.h) is pure and testable without a bus.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "audit/audit_counts.h"
#include "clock/clock_state.h"
#include "driver/sensor_state.h"
#include "modbus_tcp/modbus_request_counts.h"

namespace tiltgate {

// How long the status counts recent failures over: what "in the last 10 minutes" means on the
// console (docs/web-console.md, "Counters").
inline constexpr std::chrono::minutes kRecentFailuresWindow{10};

// Failed polls, and failed exchanges by cause (SensorCounters), over some time.
struct FailureCounts {
  std::uint64_t polls_failed = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t checksum_errors = 0;
  std::uint64_t io_errors = 0;
  std::uint64_t late_replies = 0;

  FailureCounts& operator+=(const FailureCounts& other) {
    polls_failed += other.polls_failed;
    timeouts += other.timeouts;
    checksum_errors += other.checksum_errors;
    io_errors += other.io_errors;
    late_replies += other.late_replies;
    return *this;
  }
};

// A device's exchanges on its line, attempt by attempt (driver/sensor_state.h SensorCounters;
// FC 08 counts from the same, gateway/unit_diagnostics.h): requests written, valid replies,
// replies that made no valid frame, attempts that heard nothing, refusals and the busy ones of
// them, bytes both ways, characters the port's UART lost to overruns or got with a framing or
// parity error. A bus's: its sensors' summed.
struct ExchangeCounts {
  std::uint64_t requests = 0;
  std::uint64_t replies = 0;
  std::uint64_t garbled = 0;
  std::uint64_t no_reply = 0;
  std::uint64_t refused = 0;
  std::uint64_t busy = 0;
  std::uint64_t bytes_out = 0;
  std::uint64_t bytes_in = 0;
  std::uint64_t overruns = 0;
  std::uint64_t uart_errors = 0;

  ExchangeCounts& operator+=(const ExchangeCounts& other) {
    requests += other.requests;
    replies += other.replies;
    garbled += other.garbled;
    no_reply += other.no_reply;
    refused += other.refused;
    busy += other.busy;
    bytes_out += other.bytes_out;
    bytes_in += other.bytes_in;
    overruns += other.overruns;
    uart_errors += other.uart_errors;
    return *this;
  }
};

struct SensorStatus {
  std::string name;
  std::string bus;
  int unit_id = 0;
  std::uint32_t address = 0;    // on its bus, as polled now
  std::string model;            // as the device reports it, else its driver's model
  std::string serial;           // empty until the sensor has reported it
  // [[sensor]] serial (empty: any device is served), and whether another device answers in
  // the sensor's place (status bit 6), with how many times one was found there.
  std::string configured_serial;
  bool wrong_device = false;
  std::uint64_t wrong_device_found = 0;
  std::string firmware;
  bool online = false;          // the last exchange with the sensor got a valid reply
  bool stale = true;            // no reading, or the last is older than its stale_ms
  // Degrees after mounting, as the register map serves them; none before the first reading,
  // y none on single-axis sensors.
  std::optional<double> x;
  std::optional<double> y;
  std::optional<double> tilt;
  std::optional<std::int64_t> age_ms;  // since the last reading arrived; none without one
  std::uint16_t alarms = 0;            // mapping/derived_state.h alarm_bit flags, either level
  std::uint16_t alarms_danger = 0;     // those set at the danger level
  std::uint16_t alarms_latched = 0;    // latched until acknowledged and clear
  // From the baseline (docs/monitoring.md): degrees, and millimetres at lever_m (none without
  // it); none before the first reading.
  std::optional<double> relative_x;
  std::optional<double> relative_y;
  std::optional<double> displacement_x_mm;
  std::optional<double> displacement_y_mm;
  std::optional<double> displacement_mm;
  // Degrees Celsius of the last reading, where the sensor reports a temperature.
  std::optional<double> temperature;
  // When the last reading's reply arrived, UTC; whether the clock was synchronised then.
  std::optional<std::int64_t> reading_unix_ms;
  bool clock_synchronised = true;
  std::uint64_t polls_ok = 0;
  std::uint64_t polls_failed = 0;
  // Measurement polls (ok and failed) per second over the last few seconds; none until the
  // gateway has counted for a while.
  std::optional<double> polls_per_s;
  // Why exchanges with the sensor failed (driver/sensor_state.h SensorCounters). A failed poll
  // can count under several: a time-out after a checksum error, say.
  std::uint64_t timeouts = 0;         // no valid reply in time
  std::uint64_t checksum_errors = 0;  // a reply dropped for its CRC or LRC
  std::uint64_t io_errors = 0;        // the port failed or was closed
  std::uint64_t late_replies = 0;     // answers after the time-out, discarded
  ExchangeCounts exchanges;
  std::int64_t slowest_reply_ms = 0;  // SensorCounters::slowest_reply
  // SensorCounters::reply_buckets and reply_ms_sum: the reply-time histogram.
  std::array<std::uint32_t, kReplyBucketsMs.size() + 1> reply_buckets{};
  std::uint64_t reply_ms_sum = 0;
  // Requests the sensor refused (NAK), by its protocol's refusal code; only codes seen.
  std::vector<std::pair<std::uint8_t, std::uint64_t>> refusals;
  // Seconds its bus's line spent on this sensor's polls, writes and retries, waiting for
  // replies, time-outs and late-reply guards included; and its share of the line's time over
  // the last few seconds (0..1; none until counted): who eats the line.
  double line_seconds = 0;
  std::optional<double> line_share;
  // The sensor's settings record (SensorState::settings): each setting of its model by name,
  // with the value the sensor has as far as the gateway knows; none while unknown.
  std::vector<std::pair<std::string, std::optional<double>>> settings;
  // The failures above over the last kRecentFailuresWindow (since start or the counters' reset
  // until then); none until counted.
  std::optional<FailureCounts> recent_failures;
};

// A sensor's failures since start (or its counters' reset) as one FailureCounts.
inline FailureCounts failure_counts(const SensorStatus& s) {
  return FailureCounts{s.polls_failed, s.timeouts, s.checksum_errors, s.io_errors, s.late_replies};
}

struct BusStatus {
  std::string name;
  std::string port;
  std::uint32_t baud = 0;
  std::string protocol;
  std::uint64_t polls = 0;
  std::uint64_t writes = 0;
  std::uint64_t forwarded = 0;
  // The bus's loop or a poller failed and went on (BusSchedulerStats::restarts).
  std::uint64_t restarts = 0;
  // Reply waits made longer because this machine had not handed on what the line received by
  // their deadline, and attempts given up as overloaded (LineStats; serial/serial_line.h).
  std::uint64_t machine_held = 0;
  std::uint64_t overloaded = 0;
  // Everything the line carried (LineStats): bytes written and read, commands' and forwarded
  // requests' included, and the bytes found waiting before a request, dropped unread (noise,
  // a babbling device).
  std::uint64_t bytes_out = 0;
  std::uint64_t bytes_in = 0;
  std::uint64_t stray_bytes = 0;
  std::uint64_t reopens = 0;  // its port opened again after a loss (LineStats)
  // Its black box (capture/black_box.h): how long it keeps, what it holds, and the frames its
  // memory bound pushed out before their time.
  std::int64_t black_box_s = 0;
  std::uint64_t black_box_frames = 0;
  std::uint64_t black_box_bytes = 0;
  std::uint64_t black_box_dropped = 0;
  // Its sensors' exchanges summed (add_sensor_failures).
  ExchangeCounts exchanges;
  // Where to look first when its failures make a clear pattern (gateway/line_hint.h).
  std::optional<std::string> hint;
  // Seconds the bus spent in transactions (polls, writes, forwarded requests, commands),
  // waiting for replies and time-outs included: the wire's time this bus has used.
  double busy_seconds = 0;
  // Over the last few seconds: sensor polls per second, and the share of the time the bus
  // was busy (0..1; 1 = the bus runs flat out and cannot poll faster). None until counted.
  std::optional<double> polls_per_s;
  std::optional<double> utilisation;
  // Its sensors' failures since start (or their counters' reset), and over the last
  // kRecentFailuresWindow (none until counted).
  FailureCounts failures;
  std::optional<FailureCounts> recent_failures;
};

// An on-disk store-and-forward's counters (store/record_store.h), for the metrics
// (tiltgate_store_*, labelled by the feed that keeps it).
struct StoreStats {
  std::string feed;              // "sparkplug", "mqtt"
  std::uint64_t bytes = 0;       // its files' size
  std::uint64_t records = 0;     // kept, not yet replayed
  std::uint64_t dropped = 0;     // dropped when full, oldest first, or refused (too large)
  std::uint64_t replayed = 0;    // published again
  std::uint64_t lost = 0;        // lost to a damaged file (a corrupt or torn record)
};

// The MQTT feed's counters (mqtt/mqtt_feed.h), for the metrics (tiltgate_mqtt_*).
struct MqttStats {
  std::uint64_t published = 0;   // messages handed to the broker connection
  std::uint64_t dropped = 0;     // dropped from a full backlog while the broker was away
  std::size_t backlog = 0;       // waiting for the broker now
  bool connected = false;
  std::uint64_t reconnects = 0;  // connections after the first
  StoreStats store;              // its backlog
};

// The Sparkplug B edge node's counters (sparkplug/edge_node.h), for the metrics
// (tiltgate_sparkplug_*). Commands by result: rebirth requests carried out, setting writes
// taken by the sensor or under way, refused ones (not a setting, or refused by the write path),
// whole messages ignored (commands off) and malformed ones.
struct SparkplugStats {
  bool connected = false;
  std::uint64_t published = 0;  // messages handed to the broker connection
  std::uint64_t rebirth = 0;
  std::uint64_t write = 0;
  std::uint64_t refused = 0;
  std::uint64_t ignored = 0;
  std::uint64_t malformed = 0;
  int max_commands_per_s = 0;          // [sparkplug] max_commands_per_s in force (0: no limit)
  std::uint64_t commands_delayed = 0;  // waited for their turn under it
};

// HTTP clients closed for cause since [http] last started (http/http_server.h).
struct HttpClientsClosed {
  std::uint64_t refused = 0;      // a limit reached and no connection could make room
  std::uint64_t replaced = 0;     // waiting for a whole request, closed to make room for a new one
  std::uint64_t timed_out = 0;    // no whole request within the request time-out
  std::uint64_t bad_request = 0;  // malformed or too large
};

// The HTTP server's request rates ([http] max_requests_per_s, max_client_requests_per_s; 0: no
// limit), the requests that waited for their turn under them and how long, together.
struct HttpRequestRates {
  int max_requests_per_s = 0;
  int max_client_requests_per_s = 0;
  std::uint64_t requests_delayed = 0;
  double delay_seconds = 0;
};

// The web console's logins (console/console_handler.h); all 0 without [http] users_file.
struct ConsoleCounts {
  std::uint64_t logins = 0;
  std::uint64_t login_failures = 0;    // wrong user name or password
  std::uint64_t logins_throttled = 0;  // refused with 429: too many failures lately
  std::uint64_t sessions = 0;          // open now
};

// The redundant pair's state on this gateway (docs/operations.md, "Warm standby").
struct RedundancyStatus {
  std::string configured_role;  // "primary" or "standby": [redundancy] role
  bool active = false;          // it transmits on its lines now; else it listens only
  std::uint64_t takeovers = 0;  // times it took the lines since start
  std::uint64_t step_downs = 0; // times it gave them up (a master heard, a stall, a reopen)
  double since_seconds = 0;     // Unix time the current state began
  std::string reason;           // why it is in it, in words
  std::string peer;             // [redundancy] peer, HOST:PORT
  std::int64_t takeover_ms = 0;
  bool failback = false;
  // Standby: how long since a request of the active master was last heard on any line; none
  // before the first.
  std::optional<std::int64_t> last_request_heard_ms;
};

struct GatewayStatus {
  std::vector<SensorStatus> sensors;
  std::vector<BusStatus> buses;
  std::size_t modbus_clients = 0;      // Modbus TCP connections open now
  std::uint64_t modbus_connections = 0;          // accepted since start
  std::uint64_t modbus_connections_refused = 0;  // closed at once: a limit reached, none idle
  std::uint64_t modbus_connections_replaced = 0;  // idle ones closed to make room for a new one
  std::uint64_t modbus_connections_denied = 0;    // closed at accept: not in [server] allow
  std::uint64_t modbus_writes_denied = 0;         // answered 0x01: not in [server] write_allow,
                                                  // or a TLS client's role may only read
  std::uint64_t http_connections_denied = 0;      // closed at accept: not in [http] allow
  HttpClientsClosed http_clients_closed;
  HttpRequestRates http_rates;
  ConsoleCounts console;
  std::uint64_t modbus_tls_refused = 0;           // TLS handshakes failed (certificate, version)
  // [server] max_requests_per_s and max_client_requests_per_s in force (0: no limit), the
  // requests that waited for their turn under them, and how long they waited together.
  int modbus_max_requests_per_s = 0;
  int modbus_max_client_requests_per_s = 0;
  std::uint64_t modbus_requests_delayed = 0;
  double modbus_request_delay_seconds = 0;
  std::vector<ModbusFunctionCount> modbus_requests;
  std::vector<ModbusExceptionCount> modbus_exceptions;
  std::optional<MqttStats> mqtt;      // none without [mqtt]
  std::optional<SparkplugStats> sparkplug;  // none without [sparkplug]
  std::optional<RedundancyStatus> redundancy;  // none without [redundancy]
  std::vector<StoreStats> stores;     // the feeds' stores on disk
  AuditCounts audit;                  // the audit trail's records since start
  AuditHealth audit_health;           // its disk: records held, lost, refusing now
  double process_start_seconds = 0;    // Unix time the gateway started, in seconds
  // The system clock, which readings are stamped with: synchronised, its error bound
  // (clock/clock_watch.h; filled in by the composition root, app/served_gateway.cpp).
  ClockState clock{};
  // When the configuration served now was loaded, start-up or the last reload, in local time
  // as Gateway::loaded_at() has it ("2026-12-02 05:10:22").
  std::string loaded_at{};
  // Descriptors open now and the limit of them (gateway/process_descriptors.h); none without
  // /proc.
  std::optional<double> process_open_fds;
  std::optional<double> process_max_fds;
};

// A status copy taken now: how a service asks for one.
using StatusSource = std::function<GatewayStatus()>;

}  // namespace tiltgate
