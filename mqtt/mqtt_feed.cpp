#include "mqtt/mqtt_feed.h"

#include <spdlog/spdlog.h>

#include <filesystem>

#include "driver/visible_text.h"
#include "mqtt/memory_backlog.h"
#include "mqtt/mqtt_payload.h"
#include "mqtt/stored_backlog.h"

namespace tiltgate {

namespace {

// The soonest one sensor's state follows its previous one, and the timer's period.
constexpr std::chrono::milliseconds kMinSpacing{100};
// At most this many backlog messages are replayed per tick (500 a second), after the tick's
// live messages: a full 64 MiB backlog of ~250-byte states is sent again in about 9 minutes,
// and a live state never queues behind more than one tick's replay.
constexpr std::size_t kReplayPerTick = 50;
// Drops and backlog errors are logged at most this often while the broker is away.
constexpr std::chrono::seconds kDropLogInterval{30};
// What was appended to the backlog is synced to the disk this often (and every 64 appends).
constexpr std::chrono::seconds kSyncInterval{1};
// A state directory that could not be used is tried again this often: it recovers by itself.
constexpr std::chrono::seconds kStoreRetryInterval{10};
// A broker not reached this long after start-up is warned about (once): libmosquitto only
// reports failed attempts at debug level.
constexpr std::chrono::seconds kFirstConnectWarning{10};

MqttPublisherOptions publisher_options(const MqttConfig& config) {
  MqttPublisherOptions options;
  options.topic_prefix = config.topic_prefix;
  options.pacing.interval = config.interval;
  options.pacing.on_change_deg = config.on_change_deg;
  options.pacing.min_spacing = kMinSpacing;
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
  // What is acknowledged leaves the feed's watch (mqtt/unacknowledged_messages.h).
  options.keep_acknowledged = true;
  return options;
}

BacklogLimits backlog_limits(const MqttConfig& config) {
  return {std::uint64_t(config.buffer_mb * 1024 * 1024), config.backlog};
}

// Said only when it is the cause: a state_dir of another user, or read-only.
std::string permission_hint(const std::string& error) {
  for (const char* cause : {"Permission denied", "Read-only file system", "Operation not permitted"})
    if (error.find(cause) != std::string::npos)
      return " (set [mqtt] state_dir to a directory this user may write)";
  return {};
}

std::int64_t unix_ms_now() {
  using namespace std::chrono;
  return duration_cast<milliseconds>(system_clock::now().time_since_epoch()).count();
}

}  // namespace

MqttFeed::MqttFeed(boost::asio::any_io_executor executor, StatusSource status,
                   const MqttConfig& config, MqttEventSource events)
    : timer_(executor),
      status_(std::move(status)),
      events_(std::move(events)),
      config_(config),
      publisher_(publisher_options(config)),
      client_(client_options(config)),
      replay_(kReplayPerTick),
      period_(kMinSpacing) {}

MqttFeed::~MqttFeed() { stop(); }

Expected<Done, std::string> MqttFeed::start() {
  if (auto started = client_.start(); !started) return started;
  running_ = true;
  started_at_ = Clock::now();
  // Events from now on: those before are in the event record (GET /api/events). Asked here,
  // not at construction: the monitoring is made after the feed (app/served_gateway.h).
  if (events_.last) events_sent_ = events_.last();
  if (events_.last_burst) bursts_sent_ = events_.last_burst();
  schedule();
  return Done{};
}

void MqttFeed::stop() {
  if (!running_) return;
  running_ = false;
  timer_.cancel();
  client_.stop();
  if (!backlog_) return;
  // What the broker acknowledged before the DISCONNECT is done; the rest is kept for the next
  // start, synced before the store closes.
  take_acknowledgements();
  keep_unacknowledged();
  if (auto synced = backlog_->sync(); !synced) report_backlog_error(synced.error());
  backlog_.reset();
}

MqttStats MqttFeed::stats() const {
  const std::uint64_t connections = client_.connections();
  StoreStats store = backlog_ ? backlog_->stats() : StoreStats{};
  store.feed = "mqtt";
  store.dropped += memory_counts_.dropped;
  store.replayed += memory_counts_.replayed;
  return {published_, store.dropped, static_cast<std::size_t>(store.records), client_.connected(),
          connections > 0 ? connections - 1 : 0, store};
}

void MqttFeed::schedule() {
  timer_.expires_after(period_);
  tick_waiting_ = true;
  timer_.async_wait([this](const boost::system::error_code& ec) {
    tick_waiting_ = false;
    if (ec || !running_) return;
    tick();
    schedule();
  });
}

void MqttFeed::open_backlog() {
  const BacklogLimits limits = backlog_limits(config_);
  if (!config_.state_dir.empty()) {
    const std::filesystem::path dir = std::filesystem::path(config_.state_dir) / "mqtt";
    auto stored = StoredBacklog::open(dir, limits, config_.qos);
    if (stored) {
      for (const std::string& repair : stored->repairs())
        spdlog::warn("MQTT: backlog {}: {}", visible_text(dir.string()), repair);
      if (!stored->empty())
        spdlog::info("MQTT: {} messages kept in {} from before the start", stored->stats().records,
                     visible_text(dir.string()));
      backlog_ = std::make_unique<StoredBacklog>(std::move(*stored));
      return;
    }
    // A state directory this user cannot write (a run without the package, not as root) must
    // not stop the live feed: the backlog is then kept in memory, as before the store, and
    // said loudly (docs/operations.md, "The state directory"); it is tried again meanwhile.
    spdlog::error("MQTT: {}; the backlog is kept in memory, lost on a restart, and the state "
                  "directory tried again every {} s{}",
                  stored.error(), kStoreRetryInterval.count(), permission_hint(stored.error()));
    store_tried_at_ = Clock::now();
    store_unused_ = true;
  }
  backlog_ = std::make_unique<MemoryBacklog>(limits);
}

void MqttFeed::retry_state_dir(Clock::time_point now) {
  if (!store_unused_ || now - store_tried_at_ < kStoreRetryInterval) return;
  store_tried_at_ = now;
  const std::filesystem::path dir = std::filesystem::path(config_.state_dir) / "mqtt";
  auto stored = StoredBacklog::open(dir, backlog_limits(config_), config_.qos);
  if (!stored) return;  // said when it first failed
  for (const std::string& repair : stored->repairs())
    spdlog::warn("MQTT: backlog {}: {}", visible_text(dir.string()), repair);
  // What the memory held goes after what the directory kept: both are replayed, oldest first.
  replay_.cancel();
  const StoreStats before = backlog_->stats();
  auto held = backlog_->peek(before.records);
  if (held)
    for (const MqttMessage& message : *held)
      if (auto appended = stored->append(message); !appended) report_backlog_error(appended.error());
  // The counters go on from where the memory's stood: a counter never goes back.
  memory_counts_.dropped += before.dropped;
  memory_counts_.replayed += before.replayed;
  spdlog::info("MQTT: the backlog is in {} now: {} messages moved there from memory",
               visible_text(dir.string()), held ? held->size() : 0);
  backlog_ = std::make_unique<StoredBacklog>(std::move(*stored));
  store_unused_ = false;
}

void MqttFeed::tick() {
  const auto now = Clock::now();
  if (!backlog_) open_backlog();
  retry_state_dir(now);
  // Acknowledgements first: they came for messages of the connection they were sent on.
  take_acknowledgements();
  const std::uint64_t connections = client_.connections();
  const bool connected = client_.connected();
  if (!connected || connections != connections_seen_) keep_unacknowledged();
  if (connections != connections_seen_) {
    // A broker restarted without persistence has lost the retained info: send it again.
    publisher_.forget_info();
    connections_seen_ = connections;
    if (!backlog_->empty())
      spdlog::info("MQTT: sending {} messages kept while the broker was away ({} dropped so far)",
                   backlog_->stats().records, backlog_->stats().dropped);
  }
  if (connections == 0 && !warned_unreached_ && now - started_at_ >= kFirstConnectWarning) {
    spdlog::warn("MQTT: broker not reached in {} s; still trying, keeping what is due in the "
                 "backlog",
                 kFirstConnectWarning.count());
    warned_unreached_ = true;
  }
  for (MqttMessage& message : publisher_.take(status_(), now, unix_ms_now()))
    send_or_keep(std::move(message));
  publish_events();
  if (connected) replay();
  sync_backlog(now);
  report_drops(now);
  report_notices();
}

void MqttFeed::publish_events() {
  if (events_.after) {
    for (MqttEvent& event : events_.after(events_sent_)) {
      events_sent_ = event.seq;
      send_or_keep(MqttMessage{mqtt_events_topic(config_.topic_prefix), std::move(event.payload),
                               false, event.unix_ms});
    }
  }
  if (events_.bursts_after) {
    for (MqttBurst& burst : events_.bursts_after(bursts_sent_)) {
      bursts_sent_ = burst.seq;
      send_or_keep(MqttMessage{mqtt_burst_topic(config_.topic_prefix, burst.sensor),
                               std::move(burst.payload), false, burst.unix_ms});
    }
  }
}

void MqttFeed::take_acknowledgements() {
  for (const int mid : client_.take_acknowledged()) {
    if (unacknowledged_.acknowledged(mid)) continue;
    auto replayed = replay_.acknowledged(mid, *backlog_);
    if (!replayed) report_backlog_error(replayed.error());
  }
}

void MqttFeed::keep_unacknowledged() {
  replay_.cancel();
  for (const MqttMessage& message : unacknowledged_.take_all()) keep(message);
}

void MqttFeed::send_or_keep(MqttMessage message) {
  if (const std::optional<int> mid = client_.publish(message)) {
    ++published_;
    if (message.retain) return;  // the info is sent again after a reconnect, never replayed
    for (const MqttMessage& given_up : unacknowledged_.sent(*mid, std::move(message)))
      keep(given_up);
    return;
  }
  keep(message);
}

void MqttFeed::keep(const MqttMessage& message) {
  if (message.retain) return;
  // An append may drop the oldest, which a batch being replayed may hold.
  replay_.cancel();
  MqttMessage kept = message;
  kept.payload = mqtt_historical_state_json(message.payload);
  if (auto appended = backlog_->append(kept); !appended) report_backlog_error(appended.error());
}

void MqttFeed::replay() {
  const std::uint64_t before = replay_.published();
  auto stepped = replay_.step(*backlog_, [this](const MqttMessage& message) {
    return client_.publish(message);
  });
  if (!stepped) report_backlog_error(stepped.error());
  published_ += replay_.published() - before;
}

void MqttFeed::sync_backlog(Clock::time_point now) {
  if (now - synced_at_ < kSyncInterval) return;
  synced_at_ = now;
  if (auto synced = backlog_->sync(); !synced) report_backlog_error(synced.error());
}

void MqttFeed::report_drops(Clock::time_point now) {
  const std::uint64_t dropped = backlog_->stats().dropped + memory_counts_.dropped;
  if (dropped == drops_reported_ || now - drops_reported_at_ < kDropLogInterval) return;
  spdlog::warn("MQTT: backlog full while the broker is away: {} messages dropped so far "
               "(oldest first)",
               dropped);
  drops_reported_ = dropped;
  drops_reported_at_ = now;
}

void MqttFeed::report_notices() {
  // Each is a change (the disk refusing, taking writes again, damage found): said once.
  for (const store::StoreNotice& notice : backlog_->take_notices()) {
    if (notice.problem)
      spdlog::error("MQTT: backlog: {}", notice.text);
    else
      spdlog::info("MQTT: backlog: {}", notice.text);
  }
}

void MqttFeed::report_backlog_error(const std::string& error) {
  const auto now = Clock::now();
  if (error_logged_at_ != Clock::time_point{} && now - error_logged_at_ < kDropLogInterval)
    return;
  error_logged_at_ = now;
  spdlog::error("MQTT: backlog: {}", error);
}

}  // namespace tiltgate
