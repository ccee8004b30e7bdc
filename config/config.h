// The validated configuration: what `tiltgate run --config FILE` serves. Plain data; the
// loader (config/config_loader.h) is the only place that knows TOML.
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "config/address_allow_list.h"
#include "config/tls_role_access.h"
#include "driver/family_options.h"
#include "driver/framing.h"
#include "mapping/map_definition.h"
#include "mapping/point_types.h"  // WordOrder, OfflineRead

namespace tiltgate {

// Where `tiltgate run` listens for commissioning commands, and where they look for it.
inline constexpr std::string_view kDefaultControlSocket = "/run/tiltgate/control.sock";

// Modbus/TCP Security ([server] tls): the PEM files, as resolved, and their contents, read when
// the configuration loads.
struct ServerTlsConfig {
  std::string cert_file, key_file, ca_file;
  std::string cert_pem, key_pem, ca_pem;
  std::uint16_t port = 802;

  bool operator==(const ServerTlsConfig&) const = default;
};

// Where the gateway keeps what must survive a restart (the audit trail, the MQTT backlog,
// Sparkplug's store and bdSeq); the Debian package's service has it as its StateDirectory
// (docs/operations.md, "The state directory").
inline constexpr std::string_view kDefaultStateDir = "/var/lib/tiltgate";

// [server] max_requests_per_s and max_client_requests_per_s when not given: measured on a
// 2-core box (docs/performance.md, "A flood and the line").
inline constexpr int kDefaultMaxRequestsPerSecond = 20000;
inline constexpr int kDefaultMaxClientRequestsPerSecond = 20000;

// [http] max_requests_per_s and max_client_requests_per_s when not given: 16 console sessions
// refreshing ask for about 100 a second (docs/performance.md, "A flood and the line").
inline constexpr int kDefaultHttpMaxRequestsPerSecond = 400;
inline constexpr int kDefaultHttpMaxClientRequestsPerSecond = 100;

struct ServerConfig {
  std::string listen = "0.0.0.0";
  std::uint16_t port = 502;
  int max_clients = 32;
  int max_clients_per_host = 8;            // one address's connections; more replace its idle ones
  int threads = 0;                         // threads serving Modbus TCP connections; 0: one per core
  bool plain_tcp = true;                   // false: Modbus over TLS only (needs tls)
  std::optional<ServerTlsConfig> tls;      // Modbus/TCP Security beside or instead of plain TCP
  TlsRoleAccess tls_roles;                 // tls_role_access, tls_no_role_access: a TLS client's rights
  WordOrder word_order = WordOrder::big;
  bool writes = false;                     // every write is refused with 0x01 unless true
  AddressAllowList allow;                  // who may connect (default: everyone)
  AddressAllowList write_allow;            // who may write (default: the same as allow)
  std::chrono::milliseconds idle_timeout{60000};   // a client silent this long is closed
  std::chrono::milliseconds request_timeout{5000}; // a half-sent request older than this is dropped
  std::chrono::milliseconds write_timeout{3000};   // a write still queued then is answered 0x06
  // Requests a second answered over Modbus TCP, from every client together and from each
  // connection: beyond them a request waits for its turn (doors/request_rate.h), so a
  // flood of requests never takes the cores the serial lines need. 0: no limit.
  int max_requests_per_s = kDefaultMaxRequestsPerSecond;
  int max_client_requests_per_s = kDefaultMaxClientRequestsPerSecond;
  // The Unix socket commissioning commands reach the buses through (control/control_server.h),
  // an absolute path; empty: none.
  std::string control_socket = std::string(kDefaultControlSocket);
  // Where the gateway keeps what must survive a restart: the audit trail (audit/), and the
  // default of [mqtt] and [sparkplug] state_dir. Empty (only `tiltgate demo` makes one): in
  // memory.
  std::string state_dir = std::string(kDefaultStateDir);
  // The user `tiltgate run` serves as once its ttys and listeners are open, when started as
  // root (app/run_as_user.h); empty: stay as started.
  std::string user;

  bool operator==(const ServerConfig&) const = default;
};

// The read-only HTTP status API and Prometheus metrics (http/http_server.h). Loopback by
// default: it shows every sensor's identity and angles to whoever can reach it.
struct HttpConfig {
  bool enabled = true;
  std::string listen = "127.0.0.1";
  std::uint16_t port = 8080;
  // Who may connect; without [http] allow, [server] allow (resolved by the loader).
  AddressAllowList allow;
  bool allow_given = false;  // [http] allow was written
  // Connections from one client address, of the server's 16; the next one from it replaces
  // that address's own connection waiting longest for a request, or is closed.
  int max_clients_per_host = 8;
  // Requests a second answered from every client together and from each connection: beyond
  // them a request waits for its turn (doors/request_rate.h), since a status or console
  // request copies the gateway's state on the buses' thread. 0: no limit.
  int max_requests_per_s = kDefaultHttpMaxRequestsPerSecond;
  int max_client_requests_per_s = kDefaultHttpMaxClientRequestsPerSecond;
  // The status page's graph: each sensor's angles sampled every history_interval, kept for
  // history_seconds (status/angle_history.h).
  std::chrono::seconds history_seconds{600};
  std::chrono::milliseconds history_interval{1000};
  // The web console's accounts (accounts/users_file.h), an absolute path; empty: no accounts,
  // and the API stays read-only (docs/web-console.md).
  std::string users_file;
  // HTTPS for the page, the API and the metrics: PEM files, as resolved, and their contents,
  // read when the configuration loads. Both or neither. Without them a console login is
  // accepted from loopback only.
  std::string tls_cert_file, tls_key_file;
  std::string tls_cert_pem, tls_key_pem;
  // A console session ends after this long without a request, and this long after its login
  // whatever it does.
  std::chrono::seconds session_idle{900};
  std::chrono::seconds session_max{28800};
  // The names a request's Host header may give, host names or addresses (http/host_check.h):
  // any other is answered 421, against DNS rebinding. Empty: not written, and the HTTP service
  // takes the listen address, localhost and this machine's name.
  std::vector<std::string> server_names;

  bool https() const { return !tls_cert_pem.empty(); }
  bool operator==(const HttpConfig&) const = default;
};

// The most samples a sensor's history ring may hold: 600 x 16 bytes, so even 480 sensors keep
// their history in under 5 MB.
inline constexpr std::int64_t kMaxHistorySamples = 600;


// The MQTT feed (mqtt/mqtt_feed.h): each sensor's state to a broker. Off unless the file has
// an [mqtt] table; the loader fills in the hostname defaults, so these are the values used.
struct MqttConfig {
  bool enabled = false;
  std::string host;                      // required when enabled
  std::uint16_t port = 1883;
  std::string client_id;                 // default "tiltgate-<hostname>"
  std::string topic_prefix;              // default "tiltgate/<hostname>"
  int qos = 1;
  std::chrono::milliseconds interval{1000};  // each sensor's state at least this often
  double on_change_deg = 0.01;           // sooner when an angle moved this much; 0: every reading
  int keepalive_s = 30;
  std::string username;                  // empty: none
  std::string password;
  std::string ca_file;                   // TLS when set (cert_file/key_file: client certificate)
  std::string cert_file;
  std::string key_file;
  // While the broker is away, the states not published are kept in <state_dir>/mqtt/ (the
  // store, mqtt/stored_backlog.h) within buffer_mb, and at most `backlog` of them when given.
  // An empty state_dir (only `tiltgate demo` makes one), or one that cannot be written, keeps
  // them in memory.
  std::string state_dir = std::string(kDefaultStateDir);
  double buffer_mb = 64;                 // MiB (a fraction for tests)
  std::optional<std::size_t> backlog;    // none: buffer_mb alone bounds it

  bool operator==(const MqttConfig&) const = default;
};

// The Sparkplug B edge node (sparkplug/sparkplug_service.h, docs/northbound.md "Sparkplug B"):
// off unless the file has a [sparkplug] table; the loader fills in the hostname defaults and
// resolves state_dir, so these are the values used.
struct SparkplugConfig {
  bool enabled = false;
  std::string host;                   // required with the table
  std::uint16_t port = 1883;
  std::string group_id;               // required with the table
  std::string edge_node_id;           // default: the host name
  std::string client_id;              // default "tiltgate-sparkplug-<edge_node_id>"
  std::string username;               // empty: none
  std::string password;
  std::string ca_file;                // TLS when set (cert_file/key_file: client certificate)
  std::string cert_file;
  std::string key_file;
  int keepalive_s = 30;
  std::string state_dir = std::string(kDefaultStateDir);  // bdSeq and the store, under sparkplug/
  double on_change_deg = 0.01;        // DDATA when an angle moved this much; 0: every reading
  std::chrono::milliseconds min_interval{100};
  std::chrono::milliseconds max_interval{10000};
  std::optional<std::string> primary_host_id;
  bool commands = false;              // DCMD writes settings; off: every DCMD ignored, counted
  // Messages from the broker (NCMD, DCMD, STATE) taken a second: beyond it the next one waits
  // for its turn, and the connection reads nothing meanwhile (doors/request_rate.h). 0: no
  // limit.
  int max_commands_per_s = 20;
  double buffer_mb = 64;              // the store's budget on disk, MiB (a fraction for tests)

  bool operator==(const SparkplugConfig&) const = default;
};

// The floor of late_guard's default: a few adapter round trips (USB-RS485 adapters add up to
// 16 ms each way) on top of a sensor's own slowness.
inline constexpr std::chrono::milliseconds kMinDefaultLateGuard{100};

struct BusConfig {
  std::string name;
  std::string port;                 // tty path, e.g. /dev/ttyUSB0
  // A ProtocolDescriptor name (driver/family.h). A file that names none gets the first
  // protocol of the family list.
  std::string protocol;
  std::uint32_t baud = 125000;               // the protocol's default_baud when not given
  std::chrono::milliseconds timeout{50};     // reply timeout per attempt
  int retries = 2;                            // extra attempts after a time-out (reads)
  // The most a sensor's own reply time-out may adapt up to after late replies (>= timeout).
  std::chrono::milliseconds max_timeout{500};
  // Quiet kept after a time-out before anything is sent, so a late reply is discarded and not
  // taken for the next one. Default: max_timeout - timeout (so any reply within max_timeout
  // lands in it), at least kMinDefaultLateGuard.
  std::chrono::milliseconds late_guard{450};
  // Quiet time between master packets: gap_us, else the protocol's default_gap, else 1 ms.
  std::chrono::microseconds gap{1000};
  // The bus's own framing ([[bus]] parity, stop_bits) where its protocol lets the bus choose
  // (ProtocolDescriptor::bus_chooses_framing); none: the protocol's framing.
  std::optional<Framing> framing;
  bool rs485_kernel = false;                  // TIOCSRS485 on on-board UARTs
  bool echo = false;                          // the adapter hears its own transmission
  bool low_latency = true;                    // ASYNC_LOW_LATENCY at each open (USB adapters)
  std::uint16_t master_address = 0;           // protocols where the master has an address
  std::chrono::milliseconds reopen_min{500};  // back-off when the tty disappears
  std::chrono::milliseconds reopen_max{10000};
  // Modbus unit ids whose requests are forwarded unchanged to the device with that address on
  // this bus, and its reply relayed (protocols that can: ProtocolDescriptor::forward).
  std::vector<std::uint8_t> pass_through;
  // A Modbus TCP listener of its own on [server] listen, serving only this bus's sensors, its
  // aggregates and its pass-through unit ids, so unit ids need only be unique per port. Plain
  // TCP only. None: the bus's units are served on [server] port.
  std::optional<std::uint16_t> tcp_port;
  // How much of the line's traffic its black box keeps in memory (capture/black_box.h).
  std::chrono::seconds black_box{60};
  int line = 0;                               // where it was declared, for messages

  // Every field, `line` included: reload compares settings with same_settings()
  // (gateway/config_diff.h), which leaves `line` out.
  bool operator==(const BusConfig&) const = default;
};

// A sensor mounted askew or upside down: applied to every reading before the map sees it,
// in this order: swap, invert, rotate.
struct MountingConfig {
  bool swap_axes = false;
  bool invert_x = false;
  bool invert_y = false;
  double rotate_deg = 0.0;  // rotates the X/Y frame by this angle (degrees, counter-clockwise)

  bool operator==(const MountingConfig&) const = default;
};

// One level's alarm thresholds (docs/configuration.md, "alarms"): degrees after mounting, a
// rate in degrees per second, a displacement in millimetres (SensorConfig::lever_m).
struct AlarmThresholds {
  std::optional<double> x_high, x_low, y_high, y_low;
  std::optional<double> tilt_high;             // on the tilt from vertical (mapping/tilt.h)
  std::optional<double> rate_limit_deg_s;      // |d angle / dt| on either axis above this
  std::optional<double> displacement_high_mm;  // the displacement from the baseline above this

  bool operator==(const AlarmThresholds&) const = default;
};

// A sensor's alarms at two levels: the warning level's thresholds are the keys at the table's
// top (the only level before there were two), the danger level's are `danger = {...}`. Each
// alarm sets when its value passes the threshold and has stayed past it for `hold` (for_ms),
// and clears once it is back by the hysteresis and has stayed back as long
// (line_scheduling/alarm_tracker.h).
struct AlarmConfig : AlarmThresholds {
  AlarmThresholds danger;
  double hysteresis_deg = 0.5;
  double hysteresis_mm = 0.5;
  std::chrono::milliseconds hold{0};

  bool operator==(const AlarmConfig&) const = default;
};

// The installation's reference reading (degrees after mounting): readings relative to it,
// and the displacement, are measured from here. [[sensor]] baseline sets it; a baseline set
// later (the console, `tiltgate baseline`) is kept in the state directory and wins.
struct Baseline {
  double x = 0.0;
  double y = 0.0;

  bool operator==(const Baseline&) const = default;
};

struct SensorConfig {
  std::string name;
  std::string bus;
  std::string model;                // a ModelDescriptor name (driver/family.h)
  std::uint32_t address = 0;        // bus address
  std::uint8_t unit_id = 1;         // Modbus unit id 1..247
  std::chrono::milliseconds poll{100};
  std::optional<std::chrono::milliseconds> stale_after;  // default: max(3 x poll, 1 s)
  // The serial number the sensor at `address` must report (as it reports it, trimmed): another
  // device answering there is not served as this sensor. Empty: any device is served.
  std::string serial;
  // The keys of the model's own family (FamilyDescriptor::sensor_keys), as it read them.
  FamilyOptions family_options;
  MountingConfig mounting;
  AlarmConfig alarms;
  std::optional<Baseline> baseline;  // [[sensor]] baseline; none: 0, 0 unless one was set since
  // The height of the measured point above the sensor's pivot, metres: a tilt becomes a
  // displacement there (mapping/displacement.h). None: no displacement.
  std::optional<double> lever_m;
  // Triggered bursts (docs/monitoring.md, "Bursts"): an alarm that sets, or a change faster
  // than burst_rate_deg_s, polls the sensor as fast as its line allows for `burst`, and the
  // record keeps `pre_trigger` of the samples before. Zero: no bursts.
  std::chrono::seconds burst{0};
  std::chrono::seconds pre_trigger{10};
  std::optional<double> burst_rate_deg_s;
  OfflineRead offline = OfflineRead::exception;
  double substitute = 0.0;  // offline == substitute: the value every measurement point shows
  // The register map: none for the model's built-in map; else from `map_file` (resolved
  // against the config file's directory) or written inline.
  std::optional<MapDefinition> map;
  std::string map_file;     // as resolved; empty for the built-in or an inline map
  int line = 0;

  // Every field, `line` included (see BusConfig).
  bool operator==(const SensorConfig&) const = default;
};

// One Modbus unit serving the same points of many sensors back to back (docs/configuration.md, "More than 247
// sensors"): sensor i's block starts at register i x the block's size.
struct AggregateConfig {
  std::uint8_t unit_id = 0;
  std::vector<std::string> points;   // point names of the sensors' maps, in block order
  // The sensors, in block order: as listed, or (with `bus`) that bus's sensors in file order.
  std::vector<std::string> sensors;
  std::string bus;                   // as written; empty when the sensors were listed
  int line = 0;

  bool operator==(const AggregateConfig&) const = default;
};

// [audit] (docs/configuration.md, "[audit]"): what the audit trail does when its disk refuses
// records (docs/operations.md, "A disk that refuses the trail"). Read at start.
struct AuditConfig {
  enum class WhenFull { keep, refuse };
  WhenFull when_full = WhenFull::keep;
  std::int64_t memory_kib = 1024;  // records held for a refusing disk, at most

  bool operator==(const AuditConfig&) const = default;
};

// [redundancy] (docs/configuration.md, "[redundancy]"): a warm standby on the same line
// (docs/operations.md, "Warm standby"). Read at start: a reload that changes it is refused.
struct RedundancyConfig {
  enum class Role { none, primary, standby };  // none: no [redundancy] section
  Role role = Role::none;
  std::string peer_host;   // the other gateway's Modbus TCP address ("HOST:PORT")
  std::uint16_t peer_port = 0;
  // Silence of the other master on every line before this gateway takes the lines.
  std::chrono::milliseconds takeover{2000};
  // A primary that finds the standby active takes its lines back once it has heard them for
  // takeover; off: it stays standby until the active one stops.
  bool failback = false;

  bool enabled() const { return role != Role::none; }
  bool operator==(const RedundancyConfig&) const = default;
};

// [record] (docs/configuration.md, "[record]"): each sensor's long record on the box
// (docs/monitoring.md, "The long record"): min, mean and max per interval, kept keep_days.
struct RecordConfig {
  std::chrono::seconds interval{60};
  std::uint32_t keep_days = 90;

  bool operator==(const RecordConfig&) const = default;
};

struct Config {
  std::string path;                 // the file it came from
  ServerConfig server;
  HttpConfig http;
  MqttConfig mqtt;
  SparkplugConfig sparkplug;
  AuditConfig audit;
  RedundancyConfig redundancy;
  RecordConfig record;
  std::vector<BusConfig> buses;
  std::vector<SensorConfig> sensors;
  std::vector<AggregateConfig> aggregates;
};

// The Modbus TCP listener a bus's units are served on: its tcp_port, or kMainListener for
// [server] port (and the TLS port).
inline constexpr std::uint16_t kMainListener = 0;
inline std::uint16_t listener_of(const BusConfig& bus) { return bus.tcp_port.value_or(kMainListener); }
// A sensor's: its bus's (kMainListener when the bus is unknown).
std::uint16_t listener_of(const Config& config, const SensorConfig& sensor);
// An aggregate's: its first sensor's (the loader checks that all of them share it).
std::uint16_t listener_of(const Config& config, const AggregateConfig& aggregate);

}  // namespace tiltgate
