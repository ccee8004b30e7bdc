// The transport of the MQTT feed and of the Sparkplug B edge node: one libmosquitto client
// whose network side runs on a thread of its own, so no network wait (name lookup, connect,
// send) ever happens on the gateway's event loop. A missing broker does not hold up start-up;
// every failure is retried with back-off (reconnect_min_s doubling up to reconnect_max_s).
// With a status topic (the JSON feed) it keeps <prefix>/status retained "online" while
// connected with a last will of "offline"; with a before_connect hook (Sparkplug) the hook
// gives the will of each CONNECT instead. publish() and subscribe() only hand a packet over:
// they never block on the network.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "driver/expected.h"
#include "mqtt/mqtt_message.h"

struct mosquitto;
struct mosquitto_message;

namespace tiltgate {

struct MqttClientOptions {
  std::string log_name = "MQTT";  // what its log lines start with
  std::string host;
  std::uint16_t port = 1883;
  std::string client_id;
  // <prefix>/status: "online", and "offline" as the last will; empty: no status messages
  std::string status_topic;
  int qos = 1;
  int keepalive_s = 30;
  std::string username;      // empty: none
  std::string password;
  std::string ca_file;       // empty: no TLS
  std::string cert_file;
  std::string key_file;
  int reconnect_min_s = 1;   // back-off between attempts, growing up to reconnect_max_s
  int reconnect_max_s = 30;
  // Collect the ids of acknowledged messages for take_acknowledged(); off, none are kept.
  bool keep_acknowledged = false;
};

// A CONNECT's last will.
struct MqttWill {
  std::string topic;
  std::vector<std::uint8_t> payload;
  int qos = 1;
  bool retain = false;
};

// What the client tells its owner, each on the network thread (the owner posts to its own
// event loop): none of them may call stop().
struct MqttClientHooks {
  // Before each connection attempt: the will of that CONNECT, or none to skip this attempt
  // (tried again after the back-off).
  std::function<std::optional<MqttWill>()> before_connect;
  // The CONNECT of this attempt goes out (the TCP connection to the broker is up, or a CONNACK
  // came): the will before_connect gave is now the broker's. Once per attempt at most; an
  // attempt whose TCP connect was refused or timed out sends no CONNECT and does not call it.
  std::function<void()> connect_sent;
  // The broker accepted a CONNECT (true) or the connection ended (false).
  std::function<void(bool connected)> connection;
  // A message on one of the subscriptions.
  std::function<void(std::string topic, std::vector<std::uint8_t> payload)> message;
};

// publish() and the accessors may be called from one thread (the gateway's event loop) while
// libmosquitto's thread runs the callbacks.
class MqttClient {
 public:
  explicit MqttClient(MqttClientOptions options, MqttClientHooks hooks = {});
  ~MqttClient();
  MqttClient(const MqttClient&) = delete;
  MqttClient& operator=(const MqttClient&) = delete;

  // Sets the will, credentials and TLS and starts the network thread, which connects. An error
  // is a setting libmosquitto refused (e.g. an unreadable TLS file); a broker that cannot be
  // reached is not an error: it is retried.
  Expected<Done, std::string> start();
  // Publishes "offline" (retained) when connected and there is a status topic, waits (a second
  // at most) for the last QoS 1 or 2 message to be acknowledged, disconnects and joins the
  // thread (a name lookup under way is waited for).
  void stop();

  bool connected() const { return connected_.load(); }
  std::uint64_t connections() const { return connections_.load(); }  // accepted CONNECTs so far
  // Hands `message` to libmosquitto at the configured QoS: its message id, none when not
  // connected (the caller keeps it for later).
  std::optional<int> publish(const MqttMessage& message);
  // Any message, at its own QoS; false when not connected.
  bool publish(std::string_view topic, std::span<const std::uint8_t> payload, int qos,
               bool retain);
  // With `keep_acknowledged`: the ids of the messages acknowledged since the last call (QoS 1:
  // PUBACK received; QoS 0: written to the socket), in the order they came.
  std::vector<int> take_acknowledged();
  // false when not connected.
  bool subscribe(std::string_view topic, int qos);
  // Ends the connection now (a clean DISCONNECT: no will); the next attempt follows the
  // back-off.
  void disconnect();

 private:
  void run();  // the network thread: connect, loop, back off, until stop()
  // Callbacks, status will, credentials and TLS on a fresh libmosquitto client state.
  Expected<Done, std::string> configure();
  // Before every attempt but the first: a client state with nothing of the last connection.
  // libmosquitto keeps a QoS 1 message that was not acknowledged (an NDEATH sent just before a
  // DISCONNECT) and sends it again, marked DUP, after the next CONNACK even with a clean
  // session; every connection here is a new session (clean session), whose owner sends again
  // what it still wants sent (the feed's backlog, Sparkplug's births).
  bool start_afresh();
  // The CONNECT of this attempt is on its way once the TCP connection is up.
  void notice_connect_sent();

  static void on_connect(struct mosquitto*, void* self, int rc);
  static void on_disconnect(struct mosquitto*, void* self, int rc);
  static void on_publish(struct mosquitto*, void* self, int mid);
  static void on_log(struct mosquitto*, void* self, int level, const char* text);
  static void on_message(struct mosquitto*, void* self,
                         const struct mosquitto_message* message);
  // The hook's will for the next CONNECT; false: no attempt now.
  bool prepare_connect();
  // The message id, none when libmosquitto refused it.
  std::optional<int> send(const std::string& topic, int length, const void* payload, int qos,
                          bool retain);

  MqttClientOptions options_;
  MqttClientHooks hooks_;
  struct mosquitto* mosq_ = nullptr;
  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::mutex wake_mutex_;           // wakes run()'s back-off when stop() is called
  std::condition_variable wake_;
  // Held by publish(), subscribe() and disconnect() on the caller's thread and by
  // start_afresh() on the network thread, which reinitialises the client under them.
  std::mutex client_mutex_;
  bool connect_sent_ = false;  // network thread: this attempt's CONNECT reported
  std::atomic<bool> connected_{false};
  std::atomic<std::uint64_t> connections_{0};
  int last_refusal_ = 0;  // the CONNACK code last logged, so a refusing broker logs once
  // stop() waits (briefly) for its "offline", or the last QoS 1 or 2 message, to be
  // acknowledged before disconnecting.
  std::mutex published_mutex_;
  std::condition_variable published_changed_;
  int last_published_mid_ = 0;
  int last_sent_mid_ = 0;  // of a QoS 1 or 2 message; 0: none waiting
  std::vector<int> acknowledged_;  // under published_mutex_, until take_acknowledged()
};

}  // namespace tiltgate
