#include "mqtt/mqtt_client.h"

#include <fmt/format.h>
#include <mosquitto.h>
#include <spdlog/spdlog.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

#include "driver/visible_text.h"
#include "mqtt/mqtt_payload.h"

namespace tiltgate {

namespace {

// libmosquitto wants one mosquitto_lib_init() per process before its first client.
void init_library_once() {
  static std::once_flag once;
  std::call_once(once, [] { mosquitto_lib_init(); });
}

const char* or_null(const std::string& text) { return text.empty() ? nullptr : text.c_str(); }

MqttClient& client_of(void* self) { return *static_cast<MqttClient*>(self); }

}  // namespace

MqttClient::MqttClient(MqttClientOptions options, MqttClientHooks hooks)
    : options_(std::move(options)), hooks_(std::move(hooks)) {}

MqttClient::~MqttClient() {
  stop();
  if (mosq_ != nullptr) mosquitto_destroy(mosq_);
}

Expected<Done, std::string> MqttClient::start() {
  init_library_once();
  // clean session: a restarted gateway starts afresh; what it missed is in its own backlog
  // (on disk, mqtt/stored_backlog.h).
  mosq_ = mosquitto_new(options_.client_id.c_str(), true, this);
  if (mosq_ == nullptr) return Unexpected{std::string("libmosquitto: cannot create a client")};
  if (auto configured = configure(); !configured) return configured;
  thread_ = std::thread([this] { run(); });
  return Done{};
}

Expected<Done, std::string> MqttClient::configure() {
  mosquitto_connect_callback_set(mosq_, &MqttClient::on_connect);
  mosquitto_disconnect_callback_set(mosq_, &MqttClient::on_disconnect);
  mosquitto_publish_callback_set(mosq_, &MqttClient::on_publish);
  mosquitto_log_callback_set(mosq_, &MqttClient::on_log);
  mosquitto_message_callback_set(mosq_, &MqttClient::on_message);
  int rc = MOSQ_ERR_SUCCESS;
  if (!options_.status_topic.empty()) {
    const std::string_view offline = kMqttOffline;
    rc = mosquitto_will_set(mosq_, options_.status_topic.c_str(), int(offline.size()),
                            offline.data(), options_.qos, true);
    if (rc != MOSQ_ERR_SUCCESS)
      return Unexpected{fmt::format("last will: {}", mosquitto_strerror(rc))};
  }
  if (!options_.username.empty()) {
    rc = mosquitto_username_pw_set(mosq_, options_.username.c_str(), or_null(options_.password));
    if (rc != MOSQ_ERR_SUCCESS)
      return Unexpected{fmt::format("username: {}", mosquitto_strerror(rc))};
  }
  if (!options_.ca_file.empty()) {
    rc = mosquitto_tls_set(mosq_, options_.ca_file.c_str(), nullptr, or_null(options_.cert_file),
                           or_null(options_.key_file), nullptr);
    if (rc != MOSQ_ERR_SUCCESS)
      return Unexpected{fmt::format("TLS files: {}", mosquitto_strerror(rc))};
  }
  // Publishing from the event loop while run() drives the network on its own thread.
  mosquitto_threaded_set(mosq_, true);
  return Done{};
}

bool MqttClient::start_afresh() {
  std::lock_guard lock(client_mutex_);
  if (mosquitto_reinitialise(mosq_, options_.client_id.c_str(), true, this) != MOSQ_ERR_SUCCESS) {
    spdlog::warn("{}: libmosquitto: cannot reinitialise the client", options_.log_name);
    return false;
  }
  if (auto configured = configure(); !configured) {
    spdlog::warn("{}: {}", options_.log_name, configured.error());
    return false;
  }
  return true;
}

void MqttClient::notice_connect_sent() {
  if (connect_sent_) return;
  // getpeername() answers once the TCP handshake is done; libmosquitto queued the CONNECT when
  // it began the connect and writes it as soon as the socket is writable.
  const int fd = mosquitto_socket(mosq_);
  if (fd < 0) return;
  sockaddr_storage peer{};
  socklen_t length = sizeof(peer);
  if (getpeername(fd, reinterpret_cast<sockaddr*>(&peer), &length) != 0) return;
  connect_sent_ = true;
  if (hooks_.connect_sent) hooks_.connect_sent();
}

// Our own network thread rather than mosquitto_loop_start(): libmosquitto's thread ends for
// good on a failed name lookup (MOSQ_ERR_EAI, e.g. a gateway that boots before its DNS), and
// waits for ever when the first connect_async failed (eclipse-mosquitto/mosquitto issue 1903).
// Here every failure is retried after a back-off, and stop() can wake the back-off at once.
void MqttClient::run() {
  auto delay = std::chrono::seconds(options_.reconnect_min_s);
  const auto max_delay = std::chrono::seconds(options_.reconnect_max_s);
  bool first = true;
  bool socket_open = false;
  std::optional<std::chrono::steady_clock::time_point> stop_seen;
  while (true) {
    if (stopping_.load()) {
      // The DISCONNECT stop() queued goes out first, given a second at most.
      const auto now = std::chrono::steady_clock::now();
      if (!stop_seen) stop_seen = now;
      if (!socket_open || now - *stop_seen > std::chrono::seconds(1)) break;
    }
    if (!socket_open && (first || start_afresh()) && prepare_connect()) {
      spdlog::debug("{}: connecting to {}:{}", options_.log_name, visible_text(options_.host),
                    options_.port);
      connect_sent_ = false;
      // Non-blocking TCP connect; only the name lookup can wait, and it waits on this thread.
      const int rc = mosquitto_connect_async(mosq_, options_.host.c_str(), options_.port,
                                             options_.keepalive_s);
      first = false;
      if (rc == MOSQ_ERR_SUCCESS) {
        socket_open = true;
        notice_connect_sent();  // a connect that completed at once (a broker on this host)
        continue;
      }
      spdlog::debug("{}: broker {}:{} not reached ({}); next attempt in {} s", options_.log_name,
                    visible_text(options_.host), options_.port,
                    rc == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(rc),
                    delay.count());
    } else if (socket_open) {
      // 100 ms at most in select(): a publish from the event loop wakes it sooner.
      const int rc = mosquitto_loop(mosq_, 100, 1);
      notice_connect_sent();
      if (rc == MOSQ_ERR_SUCCESS) {
        if (connected_.load()) delay = std::chrono::seconds(options_.reconnect_min_s);
        continue;
      }
      socket_open = false;
      if (stopping_.load()) break;
      spdlog::debug("{}: connection to {}:{} ended ({}); next attempt in {} s", options_.log_name,
                    visible_text(options_.host), options_.port,
                    rc == MOSQ_ERR_ERRNO ? std::strerror(errno) : mosquitto_strerror(rc),
                    delay.count());
    }
    std::unique_lock lock(wake_mutex_);
    wake_.wait_for(lock, delay, [&] { return stopping_.load(); });
    delay = std::min(delay * 2, max_delay);
  }
}

bool MqttClient::prepare_connect() {
  if (!hooks_.before_connect) return true;
  const std::optional<MqttWill> will = hooks_.before_connect();
  if (!will) return false;
  const int rc = mosquitto_will_set(mosq_, will->topic.c_str(), int(will->payload.size()),
                                    will->payload.data(), will->qos, will->retain);
  if (rc != MOSQ_ERR_SUCCESS) {
    spdlog::warn("{}: last will on {}: {}", options_.log_name, visible_text(will->topic),
                 mosquitto_strerror(rc));
    return false;
  }
  return true;
}

std::optional<int> MqttClient::send(const std::string& topic, int length, const void* payload,
                                    int qos, bool retain) {
  int mid = 0;
  {
    std::lock_guard lock(client_mutex_);
    if (mosquitto_publish(mosq_, &mid, topic.c_str(), length, payload, qos, retain) !=
        MOSQ_ERR_SUCCESS)
      return std::nullopt;
  }
  // Recorded after the publish (an acknowledgement that came first has set
  // last_published_mid_ to it already), not around it: libmosquitto's thread takes its own
  // locks before on_publish takes this one.
  if (qos > 0) {
    std::lock_guard lock(published_mutex_);
    last_sent_mid_ = mid;
  }
  return mid;
}

std::optional<int> MqttClient::publish(const MqttMessage& message) {
  if (!connected_.load()) return std::nullopt;
  return send(message.topic, int(message.payload.size()), message.payload.data(), options_.qos,
              message.retain);
}

bool MqttClient::publish(std::string_view topic, std::span<const std::uint8_t> payload, int qos,
                         bool retain) {
  if (!connected_.load()) return false;
  return send(std::string(topic), int(payload.size()), payload.data(), qos, retain).has_value();
}

std::vector<int> MqttClient::take_acknowledged() {
  std::lock_guard lock(published_mutex_);
  return std::exchange(acknowledged_, {});
}

bool MqttClient::subscribe(std::string_view topic, int qos) {
  if (!connected_.load()) return false;
  std::lock_guard lock(client_mutex_);
  return mosquitto_subscribe(mosq_, nullptr, std::string(topic).c_str(), qos) == MOSQ_ERR_SUCCESS;
}

void MqttClient::disconnect() {
  std::lock_guard lock(client_mutex_);
  if (connected_.load()) mosquitto_disconnect(mosq_);
}

void MqttClient::stop() {
  if (!thread_.joinable()) return;
  if (connected_.load()) {
    if (!options_.status_topic.empty()) {
      const std::string_view offline = kMqttOffline;
      send(options_.status_topic, int(offline.size()), offline.data(), options_.qos, true);
    }
    {
      // Acknowledged before the DISCONNECT, or given up on after a second: shutting down must
      // not hang on a broker that stopped answering.
      std::unique_lock lock(published_mutex_);
      if (last_sent_mid_ != 0)
        published_changed_.wait_for(lock, std::chrono::seconds(1),
                                    [&] { return last_published_mid_ == last_sent_mid_; });
    }
    std::lock_guard lock(client_mutex_);
    mosquitto_disconnect(mosq_);  // run() sends it, then its mosquitto_loop() ends
  }
  {
    std::lock_guard lock(wake_mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
  connected_ = false;
}

void MqttClient::on_connect(struct mosquitto* mosq, void* self, int rc) {
  MqttClient& client = client_of(self);
  client.notice_connect_sent();  // a CONNACK answers a CONNECT, even a refusing one
  if (rc != 0) {
    // A refusal (bad credentials, client id) repeats at every attempt: logged when it changes.
    if (rc != client.last_refusal_)
      spdlog::warn("{}: broker {}:{} refused the connection: {}", client.options_.log_name,
                   visible_text(client.options_.host), client.options_.port,
                   mosquitto_connack_string(rc));
    client.last_refusal_ = rc;
    return;
  }
  client.last_refusal_ = 0;
  if (!client.options_.status_topic.empty()) {
    const std::string_view online = kMqttOnline;
    mosquitto_publish(mosq, nullptr, client.options_.status_topic.c_str(), int(online.size()),
                      online.data(), client.options_.qos, true);
  }
  ++client.connections_;
  client.connected_ = true;
  spdlog::info("{}: connected to {}:{} as {}", client.options_.log_name,
               visible_text(client.options_.host), client.options_.port, client.options_.client_id);
  if (client.hooks_.connection) client.hooks_.connection(true);
}

void MqttClient::on_disconnect(struct mosquitto*, void* self, int rc) {
  MqttClient& client = client_of(self);
  if (!client.connected_.exchange(false)) return;  // a failed attempt: run() logs it
  if (client.hooks_.connection) client.hooks_.connection(false);
  if (rc == 0)
    spdlog::info("{}: disconnected from {}:{}", client.options_.log_name,
                 visible_text(client.options_.host), client.options_.port);
  else
    spdlog::warn("{}: lost the broker {}:{} ({}); reconnecting", client.options_.log_name,
                 visible_text(client.options_.host), client.options_.port,
                 rc == MOSQ_ERR_ERRNO ? "connection closed" : mosquitto_strerror(rc));
}

void MqttClient::on_publish(struct mosquitto*, void* self, int mid) {
  MqttClient& client = client_of(self);
  {
    std::lock_guard lock(client.published_mutex_);
    client.last_published_mid_ = mid;
    if (client.options_.keep_acknowledged) client.acknowledged_.push_back(mid);
  }
  client.published_changed_.notify_all();
}

void MqttClient::on_message(struct mosquitto*, void* self,
                            const struct mosquitto_message* message) {
  MqttClient& client = client_of(self);
  if (!client.hooks_.message || message == nullptr || message->topic == nullptr) return;
  const auto* bytes = static_cast<const std::uint8_t*>(message->payload);
  client.hooks_.message(std::string(message->topic),
                        std::vector<std::uint8_t>(bytes, bytes + std::max(message->payloadlen, 0)));
}

void MqttClient::on_log(struct mosquitto*, void* self, int level, const char* text) {
  // Each connection attempt ("sending CONNECT") and libmosquitto's own complaints at debug
  // level, so a broker away for hours does not fill the log; every other packet at trace.
  const std::string_view line = text;
  if (level == MOSQ_LOG_ERR || level == MOSQ_LOG_WARNING ||
      line.find("sending CONNECT") != std::string_view::npos)
    spdlog::debug("{}: libmosquitto: {}", client_of(self).options_.log_name, visible_text(line));
  else
    spdlog::trace("{}: libmosquitto: {}", client_of(self).options_.log_name, visible_text(line));
}

}  // namespace tiltgate
