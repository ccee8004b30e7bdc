// The MQTT feed's transport: one libmosquitto client whose network side runs on a thread of
// its own, so no network wait (name lookup, connect, send) ever happens on the gateway's event
// loop. A missing broker does not hold up start-up; every failure is retried with back-off
// (reconnect_min_s doubling up to reconnect_max_s). It keeps <prefix>/status retained "online" while connected with a last will of
// "offline". publish() only hands a message over: it never blocks on the network.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "driver/expected.h"
#include "mqtt/mqtt_message.h"

struct mosquitto;
struct mosquitto_message;

namespace tiltgate {

struct MqttClientOptions {
  std::string host;
  std::uint16_t port = 1883;
  std::string client_id;
  std::string status_topic;  // <prefix>/status: "online", and "offline" as the last will
  int qos = 1;
  int keepalive_s = 30;
  std::string username;      // empty: none
  std::string password;
  std::string ca_file;       // empty: no TLS
  std::string cert_file;
  std::string key_file;
  int reconnect_min_s = 1;   // back-off between attempts, growing up to reconnect_max_s
  int reconnect_max_s = 30;
};

// publish() and the accessors may be called from one thread (the gateway's event loop) while
// libmosquitto's thread runs the callbacks.
class MqttClient {
 public:
  explicit MqttClient(MqttClientOptions options);
  ~MqttClient();
  MqttClient(const MqttClient&) = delete;
  MqttClient& operator=(const MqttClient&) = delete;

  // Sets the will, credentials and TLS and starts the network thread, which connects. An error
  // is a setting libmosquitto refused (e.g. an unreadable TLS file); a broker that cannot be
  // reached is not an error: it is retried.
  Expected<Done, std::string> start();
  // Publishes "offline" (retained) when connected, disconnects and joins the thread (a name
  // lookup under way is waited for).
  void stop();

  bool connected() const { return connected_.load(); }
  std::uint64_t connections() const { return connections_.load(); }  // accepted CONNECTs so far
  // Hands `message` to libmosquitto at the configured QoS: its message id, none when not
  // connected (the caller keeps it for later).
  std::optional<int> publish(const MqttMessage& message);
  // The ids of the messages acknowledged since the last call (QoS 1: PUBACK received; QoS 0:
  // written to the socket), in the order they came.
  std::vector<int> take_acknowledged();

 private:
  void run();  // the network thread: connect, loop, back off, until stop()

  static void on_connect(struct mosquitto*, void* self, int rc);
  static void on_disconnect(struct mosquitto*, void* self, int rc);
  static void on_publish(struct mosquitto*, void* self, int mid);
  static void on_log(struct mosquitto*, void* self, int level, const char* text);

  MqttClientOptions options_;
  struct mosquitto* mosq_ = nullptr;
  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::mutex wake_mutex_;           // wakes run()'s back-off when stop() is called
  std::condition_variable wake_;
  std::atomic<bool> connected_{false};
  std::atomic<std::uint64_t> connections_{0};
  int last_refusal_ = 0;  // the CONNACK code last logged, so a refusing broker logs once
  // stop() waits (briefly) for its "offline" to be acknowledged before disconnecting.
  std::mutex published_mutex_;
  std::condition_variable published_changed_;
  int last_published_mid_ = 0;
  std::vector<int> acknowledged_;  // under published_mutex_, until take_acknowledged()
};

}  // namespace tiltgate
