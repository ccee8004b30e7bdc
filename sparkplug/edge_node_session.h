// The Sparkplug B edge node's session rules (Sparkplug 3.0.0, chapter 5 "Operational
// Behavior"), without a broker or a clock: the caller reports the connection's events, the
// messages that arrive and the sensors' samples, with the time, and gets back what to do, in
// order. One session per gateway, one device per [[sensor]].
//
// The caller's part, with libmosquitto:
//   1. before every connection attempt: begin_connect() gives the NDEATH will (set it with
//      mosquitto_will_set) and its bdSeq, which the caller stores (state_dir) before
//      connecting, and hands back to create() after a restart; once the attempt's CONNECT
//      went out (the TCP connection is up): connect_sent(). bdSeq goes up by one per CONNECT
//      sent (tck-id-topics-nbirth-bdseq-increment): an attempt refused before its CONNECT
//      leaves it for the next attempt;
//   2. on CONNACK: on_connected(); on a lost connection: on_connection_lost();
//   3. every message on a subscribed topic: on_message();
//   4. periodically (every 100 ms, say) with every sensor's sample: update(); and with the
//      node's own (the clock), update_node(), first before the first connection;
//   5. a clean stop: stop().
// Each returns Actions, to be carried out in order before the session is called again:
// Subscribe and Publish go to the broker, in that order (a Publish's seq is given when it is
// made, and the seq must follow the order on the wire); Keep goes to the store-and-forward
// (store/record_store.h) and comes back through replay(); Write is a setting write for the
// sensor's bus; Disconnect ends the connection (reconnect later, from step 1).
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "driver/expected.h"
#include "sparkplug/device_metrics.h"
#include "sparkplug/payload.h"
#include "sparkplug/report_by_exception.h"
#include "sparkplug/topic.h"

namespace tiltgate::sparkplug {

struct EdgeNodeOptions {
  std::string group_id;
  std::string edge_node_id;
  // Publish births only while this host's STATE says online (tck-id-message-flow-edge-node-
  // birth-publish-phid-wait); none: births as soon as the session is established.
  std::optional<std::string> primary_host_id;
  NodeInfo node;
  // DDATA when angle_x or angle_y moved this much since the device's last DDATA (0: at every
  // new reading), when status, online, stale, alarms, identity or a setting changed, and at
  // least every max_interval; never sooner than min_interval after the device's last message.
  double on_change_deg = 0.01;
  std::chrono::milliseconds min_interval{100};
  std::chrono::milliseconds max_interval{10000};
  bool commands = false;  // DCMD writes settings; when false every DCMD is ignored and counted
};

// The time, twice: steady for pacing (a clock step does not stall or flood the feed), Unix ms
// (UTC) for the payloads' timestamps.
struct Instant {
  std::chrono::steady_clock::time_point steady;
  std::int64_t unix_ms = 0;
};

struct Subscribe {
  std::string topic;
  int qos = 1;
};

struct Publish {
  std::string topic;
  Payload payload;
  int qos = 0;
  bool retain = false;

  std::vector<std::uint8_t> bytes() const { return encode(payload); }
};

// A DDATA that could not be published (the broker away, or the primary host offline), for the
// store-and-forward: its metrics are named (not aliased) and historical, it has no seq, and
// replay() makes it publishable once the session is live again. `time_unix_ms` is the reading's.
struct Keep {
  std::string topic;
  Payload payload;
  std::int64_t time_unix_ms = 0;
};

// A DCMD's request to write a setting; the caller carries it out like a Modbus write (same
// range checks, same queue); the new value shows in a later DDATA once the sample has it.
struct Write {
  std::string device;
  std::string setting;  // as in DeviceSample::settings
  double value = 0;
};

struct Disconnect {};

using Action = std::variant<Subscribe, Publish, Keep, Write, Disconnect>;

// The MQTT CONNECT's will: NDEATH with the bdSeq metric, QoS 1, not retained
// (tck-id-payloads-ndeath-will-message-qos, -retain, tck-id-payloads-ndeath-bdseq).
struct Will {
  std::string topic;
  Payload payload;
  int qos = 1;
  bool retain = false;
  std::uint8_t bd_seq = 0;
};

// Commands received: NCMD and DCMD metrics looked at (rebirth, write, refused: not a rebirth
// request or a writable setting of a born device, or a value that is not a number), and whole
// messages not looked at (ignored: a DCMD with commands off, or a rebirth before the births;
// malformed: a payload, topic or STATE that does not parse).
struct CommandCounts {
  std::uint64_t rebirth = 0;
  std::uint64_t write = 0;
  std::uint64_t refused = 0;
  std::uint64_t ignored = 0;
  std::uint64_t malformed = 0;
};

enum class SessionState {
  disconnected,      // no MQTT connection
  connecting,        // CONNECT sent with the will, no CONNACK yet
  waiting_for_host,  // connected and subscribed; the primary host is not online
  live,              // births published: data goes to the broker
};

enum class ReplayRefusal {
  not_live,        // no births yet: keep it for later
  unknown_device,  // the topic names no device of this node (the configuration changed)
  device_offline,  // the device has no DBIRTH now
  malformed,       // not a kept DDATA, or none of its metrics is in the device's birth
};

class EdgeNodeSession {
 public:
  // A session for `devices` (the sensors' names, in configuration order: their aliases follow
  // it). `last_bd_seq` is the bdSeq of the previous CONNECT as stored (that of the last will
  // begin_connect() gave: it may not have gone out), none on a first start.
  // Fails when an id is not a valid Sparkplug id, a device name repeats, or the intervals are
  // not min ≤ max.
  static Expected<EdgeNodeSession, std::string> create(EdgeNodeOptions options,
                                                       std::vector<std::string> devices,
                                                       std::optional<std::uint8_t> last_bd_seq);

  Will begin_connect(Instant now);
  void connect_sent();
  std::vector<Action> on_connected(Instant now);
  void on_connection_lost();
  std::vector<Action> on_message(std::string_view topic, std::span<const std::uint8_t> payload,
                                 Instant now);
  std::vector<Action> update(std::span<const DeviceSample> samples, Instant now);
  // The node's own state (the system clock): kept for the next NBIRTH, and while live an NDATA
  // of what changed (node_data_metrics: Clock/error_ms at most every max_interval while it
  // only drifts).
  std::vector<Action> update_node(const NodeSample& sample, Instant now);
  // A clean stop: NDEATH (QoS 1) and Disconnect when connected
  // (tck-id-operational-behavior-edge-node-intentional-disconnect-ndeath).
  std::vector<Action> stop(Instant now);

  // A kept DDATA (Keep, as encoded into the store) made publishable: aliases for its named
  // metrics, the next seq and the publishing time; historical and the readings' timestamps
  // stay. Publish it at once, before calling the session again.
  Expected<Publish, ReplayRefusal> replay(std::string_view topic,
                                          std::span<const std::uint8_t> payload, Instant now);

  SessionState state() const { return state_; }
  std::uint8_t bd_seq() const { return bd_seq_; }
  const CommandCounts& commands() const { return commands_; }
  const EdgeNodeOptions& options() const { return options_; }

 private:
  struct Device {
    std::string name;
    std::optional<DeviceSample> sample;  // the latest
    bool born = false;                   // a DBIRTH in this session, no DDEATH since
    std::vector<MetricSlot> layout;      // of the last message
    LastReport last;                     // what the last message reported, by layout slot
  };

  EdgeNodeSession(EdgeNodeOptions options, std::vector<Device> devices,
                  std::optional<std::uint8_t> last_bd_seq);

  std::uint64_t next_seq();
  std::string node_topic_for(MessageType type) const;
  std::string device_topic_for(MessageType type, const Device& device) const;
  Device* find_device(std::string_view name);
  std::size_t index_of(const Device& device) const;
  Payload ndeath_payload(Instant now) const;

  void births(std::vector<Action>& out, Instant now);
  void device_birth(std::vector<Action>& out, Device& device, Instant now);
  void device_update(std::vector<Action>& out, Device& device, const DeviceSample& sample,
                     Instant now);
  ExceptionRules exception_rules() const;
  std::vector<Metric> data_metrics(const Device& device, const std::vector<Value>& values,
                                   const std::vector<std::size_t>& slots, bool named,
                                   std::uint64_t timestamp) const;

  void node_command(std::vector<Action>& out, std::span<const std::uint8_t> payload, Instant now);
  void device_command(std::vector<Action>& out, std::string_view device,
                      std::span<const std::uint8_t> payload);
  void host_state(std::vector<Action>& out, std::span<const std::uint8_t> payload, Instant now);

  EdgeNodeOptions options_;
  std::vector<Device> devices_;
  std::optional<std::uint8_t> last_bd_seq_;  // of the last CONNECT sent
  std::uint8_t bd_seq_ = 0;                  // of the will begin_connect() gave last
  std::uint8_t seq_ = 0;  // the next message's
  SessionState state_ = SessionState::disconnected;
  std::optional<std::uint64_t> host_timestamp_;  // of the last STATE accepted
  NodeSample node_;                               // the latest
  NodeSample node_reported_;                      // in the last NBIRTH or NDATA
  std::chrono::steady_clock::time_point node_reported_at_{};
  CommandCounts commands_;
};

}  // namespace tiltgate::sparkplug
