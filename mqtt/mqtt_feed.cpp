#include "mqtt/mqtt_feed.h"

#include <spdlog/spdlog.h>

#include "mqtt/mqtt_payload.h"

namespace tiltgate {

namespace {

// The soonest one sensor's state follows its previous one, and the timer's period.
constexpr std::chrono::milliseconds kMinSpacing{100};
// At most this many backlog messages go to libmosquitto per tick, so a long backlog is handed
// over in slices and the event loop is never held for long.
constexpr std::size_t kFlushPerTick = 1000;
// Drops are logged at most this often while the broker is away.
constexpr std::chrono::seconds kDropLogInterval{30};
// A broker not reached this long after start-up is warned about (once): libmosquitto only
// reports failed attempts at debug level.
constexpr std::chrono::seconds kFirstConnectWarning{10};

MqttPublisherOptions publisher_options(const MqttConfig& config) {
  MqttPublisherOptions options;
  options.topic_prefix = config.topic_prefix;
  options.pacing.interval = config.interval;
  options.pacing.on_change_deg = config.on_change_deg;
  options.pacing.min_spacing = kMinSpacing;
  options.backlog = config.backlog;
  return options;
}

MqttClientOptions client_options(const MqttConfig& config) {
  MqttClientOptions options;
  options.host = config.host;
  options.port = config.port;
  options.client_id = config.client_id;
  options.status_topic = mqtt_status_topic(config.topic_prefix);
  options.qos = config.qos;
  options.keepalive_s = config.keepalive_s;
  options.username = config.username;
  options.password = config.password;
  options.ca_file = config.ca_file;
  options.cert_file = config.cert_file;
  options.key_file = config.key_file;
  return options;
}

std::int64_t unix_ms_now() {
  using namespace std::chrono;
  return duration_cast<milliseconds>(system_clock::now().time_since_epoch()).count();
}

}  // namespace

MqttFeed::MqttFeed(boost::asio::any_io_executor executor, StatusSource status,
                   const MqttConfig& config)
    : timer_(executor),
      status_(std::move(status)),
      publisher_(publisher_options(config)),
      client_(client_options(config)),
      period_(kMinSpacing),
      backlog_capacity_(config.backlog) {}

MqttFeed::~MqttFeed() { stop(); }

Expected<Done, std::string> MqttFeed::start() {
  if (auto started = client_.start(); !started) return started;
  running_ = true;
  started_at_ = std::chrono::steady_clock::now();
  schedule();
  return Done{};
}

void MqttFeed::stop() {
  if (!running_) return;
  running_ = false;
  timer_.cancel();
  client_.stop();
}

MqttStats MqttFeed::stats() const {
  const std::uint64_t connections = client_.connections();
  return {published_, publisher_.backlog().dropped(), publisher_.backlog().size(),
          client_.connected(), connections > 0 ? connections - 1 : 0};
}

void MqttFeed::schedule() {
  timer_.expires_after(period_);
  timer_.async_wait([this](const boost::system::error_code& ec) {
    if (ec || !running_) return;
    tick();
    schedule();
  });
}

void MqttFeed::tick() {
  const auto now = std::chrono::steady_clock::now();
  const std::uint64_t connections = client_.connections();
  if (connections != connections_seen_) {
    // A broker restarted without persistence has lost the retained info: send it again.
    publisher_.forget_info();
    connections_seen_ = connections;
    if (!publisher_.backlog().empty())
      spdlog::info("MQTT: sending {} messages kept while the broker was away ({} dropped so far)",
                   publisher_.backlog().size(), publisher_.backlog().dropped());
  }
  if (connections == 0 && !warned_unreached_ && now - started_at_ >= kFirstConnectWarning) {
    spdlog::warn("MQTT: broker not reached in {} s; still trying, keeping up to {} messages",
                 kFirstConnectWarning.count(), backlog_capacity_);
    warned_unreached_ = true;
  }
  publisher_.take(status_(), now, unix_ms_now());
  flush();
  report_drops(now);
}

void MqttFeed::flush() {
  MqttBacklog& backlog = publisher_.backlog();
  for (std::size_t sent = 0; sent < kFlushPerTick && !backlog.empty(); ++sent) {
    if (!client_.publish(backlog.front())) return;  // kept for the next connection
    backlog.pop();
    ++published_;
  }
}

void MqttFeed::report_drops(std::chrono::steady_clock::time_point now) {
  const std::uint64_t dropped = publisher_.backlog().dropped();
  if (dropped == drops_reported_ || now - drops_reported_at_ < kDropLogInterval) return;
  spdlog::warn("MQTT: backlog full while the broker is away: {} messages dropped so far "
               "(oldest first)",
               dropped);
  drops_reported_ = dropped;
  drops_reported_at_ = now;
}

}  // namespace tiltgate
