#include "sparkplug/edge_node.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <boost/asio/co_spawn.hpp>
#include <boost/asio/post.hpp>
#include <future>
#include <thread>
#include <system_error>
#include <utility>

#include "driver/visible_text.h"
#include "sparkplug/bd_seq_file.h"
#include "store/file_io.h"

namespace tiltgate::sparkplug {

namespace {

namespace fs = std::filesystem;

constexpr std::chrono::milliseconds kTick{100};
constexpr std::uint64_t kSyncEveryTicks = 10;  // the store's fsync once a second
// Refused writes, malformed messages and store errors are logged at most this often.
constexpr std::chrono::seconds kLogInterval{30};
// A broker not reached this long after the start is warned about (once): libmosquitto reports
// failed attempts at debug level only.
constexpr std::chrono::seconds kFirstConnectWarning{10};
// How often a CONNECT waiting for its will looks whether the edge node is stopping.
constexpr std::chrono::milliseconds kWillPoll{50};

EdgeNodeOptions session_options(const SparkplugConfig& config, const Gateway& gateway) {
  EdgeNodeOptions options;
  options.group_id = config.group_id;
  options.edge_node_id = config.edge_node_id;
  options.primary_host_id = config.primary_host_id;
  options.node.version = TILTGATE_VERSION;
  options.node.buses = static_cast<std::uint32_t>(gateway.config().buses.size());
  options.on_change_deg = config.on_change_deg;
  options.min_interval = config.min_interval;
  options.max_interval = config.max_interval;
  options.commands = config.commands;
  return options;
}

MqttClientOptions client_options(const SparkplugConfig& config) {
  MqttClientOptions options;
  options.log_name = "Sparkplug";
  options.host = config.host;
  options.port = config.port;
  options.client_id = config.client_id;
  options.keepalive_s = config.keepalive_s;
  options.username = config.username;
  options.password = config.password;
  options.ca_file = config.ca_file;
  options.cert_file = config.cert_file;
  options.key_file = config.key_file;
  return options;  // no status topic: NDEATH is the will, set before each CONNECT
}

// The clock's state as the node's metrics report it.
NodeSample node_sample(const ClockState& clock) {
  return NodeSample{clock.synchronised, clock.error_ms};
}

bool due(std::chrono::steady_clock::time_point& last, std::chrono::steady_clock::time_point now) {
  if (last != std::chrono::steady_clock::time_point{} && now - last < kLogInterval) return false;
  last = now;
  return true;
}

}  // namespace

EdgeNode::EdgeNode(boost::asio::any_io_executor executor, const Gateway& gateway,
                   FamilyList families, const SparkplugConfig& config, ClockReader clock,
                   monitoring::BurstSource bursts)
    : executor_(executor),
      timer_(executor),
      gateway_(gateway),
      config_(config),
      clock_(std::move(clock)),
      bursts_(std::move(bursts)),
      dir_(fs::path(config.state_dir) / "sparkplug"),
      sampler_(gateway, families),
      writer_(gateway, families),
      command_rate_(config.max_commands_per_s) {}

EdgeNode::~EdgeNode() { stop(); }

template <class Handler>
void EdgeNode::post(Handler handler) {
  boost::asio::post(executor_, [alive = alive_, handler = std::move(handler)]() mutable {
    if (alive->load()) handler();
  });
}

Expected<Done, std::string> EdgeNode::start(std::optional<std::uint8_t> last_bd_seq) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec)
    return Unexpected(fmt::format("state_dir: cannot create {}: {}", dir_.string(), ec.message()));
  // Said now rather than at the first CONNECT: a state_dir the service user cannot write.
  const fs::path probe = dir_ / "write-check";
  if (auto written = store::replace_file(probe, {}); !written)
    return Unexpected(fmt::format("state_dir {} is not writable: {}", dir_.string(),
                                  written.error()));
  fs::remove(probe, ec);
  // A directory where bdSeq should be would refuse every write of it (store/file_io.h).
  for (const char* name : {"bdSeq", "bdSeq.tmp"}) {
    if (auto cleared = store::clear_way_for_file(dir_ / name); !cleared)
      spdlog::error("Sparkplug: {}", cleared.error());
    else if (*cleared)
      spdlog::warn("Sparkplug: {}: {}", dir_.string(), **cleared);
  }
  // The edge node before this one in the process may have used a bdSeq the disk refused.
  if (!last_bd_seq) {
    if (auto stored = read_bd_seq(dir_ / "bdSeq"); stored)
      last_bd_seq = *stored;
    else
      spdlog::warn("Sparkplug: {}; bdSeq starts again at 0", stored.error());
  }
  auto backlog =
      DdataBacklog::open(dir_ / "store", std::uint64_t(config_.buffer_mb * 1024 * 1024));
  if (!backlog) return Unexpected(fmt::format("state_dir: the store: {}", backlog.error()));
  for (const std::string& repair : backlog->store().repairs())
    spdlog::warn("Sparkplug: store repaired: {}", repair);
  if (backlog->store().records() > 0)
    spdlog::info("Sparkplug: {} DDATA kept from before, replayed after the births",
                 backlog->store().records());
  std::vector<std::string> devices;
  for (const SensorConfig& sensor : gateway_.config().sensors) devices.push_back(sensor.name);
  auto session = EdgeNodeSession::create(session_options(config_, gateway_), std::move(devices),
                                         last_bd_seq);
  if (!session) return Unexpected(session.error());
  last_bd_seq_ = last_bd_seq;
  session_.emplace(std::move(*session));
  // Bursts from now on: those before are in their files (tiltgate bursts, the console).
  if (bursts_.last) bursts_kept_ = bursts_.last();
  // Before the first CONNACK, which may come before the first tick: the NBIRTH has the clock.
  (void)session_->update_node(node_sample(clock_()), now());
  backlog_.emplace(std::move(*backlog));

  MqttClientHooks hooks;
  hooks.before_connect = [this] { return prepare_connect(); };
  // Posted after the will's begin_connect() and before the CONNACK's on_connected().
  hooks.connect_sent = [this] { post([this] { session_->connect_sent(); }); };
  hooks.connection = [this](bool connected) {
    post([this, connected] {
      if (connected)
        carry_out(session_->on_connected(now()));
      else
        session_->on_connection_lost();
    });
  };
  hooks.message = [this](std::string topic, std::vector<std::uint8_t> payload) {
    // A flood of commands waits for its turns here, on the network thread: it reads nothing
    // meanwhile and the broker holds the rest, so the buses' thread (where each is handled)
    // keeps its time for the lines.
    const auto arrived = std::chrono::steady_clock::now();
    if (const auto turn = command_rate_.reserve(arrived); turn > arrived) {
      ++commands_delayed_;
      std::this_thread::sleep_until(turn);
    }
    post([this, topic = std::move(topic), payload = std::move(payload)] {
      const std::uint64_t malformed = session_->commands().malformed;
      carry_out(session_->on_message(topic, payload, now()));
      if (session_->commands().malformed != malformed &&
          due(malformed_logged_at_, std::chrono::steady_clock::now()))
        spdlog::warn("Sparkplug: a malformed message on {} ignored ({} so far)",
                     visible_text(topic), session_->commands().malformed);
    });
  };
  client_ = std::make_unique<MqttClient>(client_options(config_), std::move(hooks));
  if (auto started = client_->start(); !started) return started;
  running_ = true;
  started_at_ = std::chrono::steady_clock::now();
  schedule();
  return Done{};
}

std::optional<MqttWill> EdgeNode::prepare_connect() {
  auto promise = std::make_shared<std::promise<std::optional<MqttWill>>>();
  std::future<std::optional<MqttWill>> will = promise->get_future();
  post([this, promise] { promise->set_value(begin_connect()); });
  while (will.wait_for(kWillPoll) != std::future_status::ready)
    if (!alive_->load()) return std::nullopt;
  return will.get();
}

std::optional<MqttWill> EdgeNode::begin_connect() {
  const Will will = session_->begin_connect(now());
  last_bd_seq_ = will.bd_seq;
  // Stored before the CONNECT that uses it: after a restart the next one is one more
  // (tck-id-topics-nbirth-bdseq-increment). One the disk refuses does not keep the node
  // offline: the session's next bdSeq, held in memory, still goes up by one at each CONNECT,
  // which is what a host needs to see it alive; only a restart before it is stored may use a
  // value again (docs/northbound.md, "What a host sees"). Attempts refused before their
  // CONNECT offer the same bdSeq again: written once.
  if (stored_bd_seq_ != will.bd_seq) {
    if (auto stored = write_bd_seq(dir_ / "bdSeq", will.bd_seq); stored)
      stored_bd_seq_ = will.bd_seq;
    else if (due(bd_seq_error_logged_at_, std::chrono::steady_clock::now()))
      spdlog::error("Sparkplug: bdSeq {} not stored ({}); connecting with it all the same, a "
                    "restart before it is stored may use it again",
                    will.bd_seq, stored.error());
  }
  spdlog::debug("Sparkplug: connecting with bdSeq {}", will.bd_seq);
  return MqttWill{will.topic, encode(will.payload), will.qos, will.retain};
}

void EdgeNode::stop() {
  if (!running_) return;
  running_ = false;
  timer_.cancel();
  // NDEATH (QoS 1) before the DISCONNECT (tck-id-operational-behavior-edge-node-intentional-
  // disconnect-ndeath); client_->stop() waits for its acknowledgement, then disconnects.
  for (const Action& action : session_->stop(now()))
    if (const auto* message = std::get_if<Publish>(&action)) publish(*message);
  alive_->store(false);
  client_->stop();
  if (auto synced = backlog_->sync(); !synced)
    spdlog::warn("Sparkplug: store not synced: {}", synced.error());
}

Instant EdgeNode::now() const {
  using namespace std::chrono;
  return Instant{steady_clock::now(),
                 duration_cast<milliseconds>(system_clock::now().time_since_epoch()).count()};
}

void EdgeNode::schedule() {
  timer_.expires_after(kTick);
  tick_waiting_ = true;
  timer_.async_wait([this](const boost::system::error_code& ec) {
    tick_waiting_ = false;
    if (ec || !running_) return;
    tick();
    schedule();
  });
}

void EdgeNode::tick() {
  const Instant at = now();
  log_refusal_summaries();
  if (client_->connections() == 0 && !warned_unreached_ &&
      at.steady - started_at_ >= kFirstConnectWarning) {
    spdlog::warn("Sparkplug: broker {}:{} not reached in {} s; still trying, keeping the data "
                 "in {}",
                 config_.host, config_.port, kFirstConnectWarning.count(), dir_.string());
    warned_unreached_ = true;
  }
  carry_out(session_->update_node(node_sample(clock_()), at));
  carry_out(session_->update(sampler_.sample(at.steady, at.unix_ms), at));
  keep_bursts();
  // After the live data of this tick: the replay never holds it up.
  if (client_->connected()) {
    auto replayed = backlog_->replay(*session_, at, kReplayPerTick,
                                     [this](const Publish& message) { return publish(message); });
    if (!replayed && due(store_error_logged_at_, at.steady))
      spdlog::error("Sparkplug: store replay: {}", replayed.error());
  }
  const std::uint64_t dropped = backlog_->counts().dropped;
  if (dropped != drops_logged_ && due(drops_logged_at_, at.steady)) {
    spdlog::warn("Sparkplug: store full ({} MiB) while the broker is away: {} DDATA dropped so "
                 "far (oldest first)",
                 config_.buffer_mb, dropped);
    drops_logged_ = dropped;
  }
  if (++ticks_ % kSyncEveryTicks == 0) {
    if (auto synced = backlog_->sync(); !synced && due(store_error_logged_at_, at.steady))
      spdlog::error("Sparkplug: store not synced: {}", synced.error());
  }
  // Each is a change (the disk refusing, taking writes again, damage found): said once.
  for (const store::StoreNotice& notice : backlog_->take_notices()) {
    if (notice.problem)
      spdlog::error("Sparkplug: store: {}", notice.text);
    else
      spdlog::info("Sparkplug: store: {}", notice.text);
  }
}

void EdgeNode::keep_bursts() {
  if (!bursts_.after) return;
  for (const monitoring::BurstBatch& batch : bursts_.after(bursts_kept_, kReplayPerTick)) {
    bursts_kept_ = batch.seq;
    std::vector<Metric> metrics = burst_metrics(batch);
    if (metrics.empty()) continue;
    const std::int64_t newest = batch.samples.back().unix_ms;
    carry_out({Keep{device_topic(MessageType::DDATA, config_.group_id, config_.edge_node_id,
                                 batch.sensor),
                    Payload{static_cast<std::uint64_t>(now().unix_ms), std::nullopt,
                            std::move(metrics)},
                    newest}});
  }
}

bool EdgeNode::publish(const Publish& message) {
  const std::vector<std::uint8_t> bytes = message.bytes();
  if (!client_->publish(message.topic, bytes, message.qos, message.retain)) return false;
  ++published_;
  return true;
}

void EdgeNode::carry_out(std::vector<Action> actions) {
  for (Action& action : actions) {
    if (const auto* subscribe = std::get_if<Subscribe>(&action)) {
      client_->subscribe(subscribe->topic, subscribe->qos);
    } else if (const auto* message = std::get_if<Publish>(&action)) {
      if (!publish(*message))
        spdlog::debug("Sparkplug: {} not sent: not connected", message->topic);
    } else if (const auto* keep = std::get_if<Keep>(&action)) {
      if (auto kept = backlog_->keep(*keep);
          !kept && due(store_error_logged_at_, std::chrono::steady_clock::now()))
        spdlog::error("Sparkplug: a DDATA not kept (counted as dropped): {}", kept.error());
    } else if (auto* write = std::get_if<Write>(&action)) {
      write_setting(std::move(*write));
    } else if (std::holds_alternative<Disconnect>(action)) {
      client_->disconnect();  // the primary host went offline: connect again later
    }
  }
}

void EdgeNode::write_setting(Write write) {
  ++writes_in_flight_;  // writer_ is this node's: it stays until the write is answered
  // Who asked, in the audit trail's words (audit/audit_record.h): the primary host, when the
  // node has one (a DCMD names no sender).
  WriteOrigin origin{"sparkplug", config_.primary_host_id
                                      ? "host " + *config_.primary_host_id
                                      : std::string("a DCMD")};
  boost::asio::co_spawn(
      executor_, writer_.write(write.device, write.setting, write.value, std::move(origin)),
      [this, write](std::exception_ptr error, SettingOutcome outcome) {
        --writes_in_flight_;
        if (!error && outcome.result == SettingOutcome::Result::ack) {
          spdlog::info("Sparkplug: DCMD wrote {} = {} on {}", visible_text(write.setting),
                       write.value, visible_text(write.device));
          return;
        }
        // With an exception co_spawn hands over a default outcome (refused, no detail): the
        // reason is then ours. A NAK, a time-out or a refusal is logged with its detail.
        std::string why = error ? std::string("the write failed inside the gateway")
                                : std::move(outcome.detail);
        if (why.empty()) why = "refused";
        ++writes_refused_;
        // Throttled per sensor by count: the first few of each minute in full, the rest summed
        // up in one line (log_refusal_summaries()).
        if (refusal_log_.admit(write.device, std::chrono::steady_clock::now()))
          spdlog::warn("Sparkplug: DCMD write of {} = {} on {} refused: {} ({} refused so far)",
                       visible_text(write.setting), write.value, visible_text(write.device),
                       visible_text(why), writes_refused_);
        log_refusal_summaries();
      });
}

void EdgeNode::log_refusal_summaries() {
  for (const SuppressedProblems& summary :
       refusal_log_.take_summaries(std::chrono::steady_clock::now()))
    spdlog::warn("Sparkplug: {} more DCMD write(s) on {} refused in {} s, not logged one by one",
                 summary.count, summary.address,
                 std::chrono::duration_cast<std::chrono::seconds>(summary.span).count());
}

// Its timer's handler too: cancelling does not take back one the timer's expiry already queued.
bool EdgeNode::finished() const { return !running_ && writes_in_flight_ == 0 && !tick_waiting_; }

SparkplugStats EdgeNode::stats() const {
  SparkplugStats stats;
  stats.connected = client_ && client_->connected();
  stats.published = published_;
  if (session_) {
    const CommandCounts& commands = session_->commands();
    stats.rebirth = commands.rebirth;
    stats.write = commands.write - std::min(commands.write, writes_refused_);
    stats.refused = commands.refused + writes_refused_;
    stats.ignored = commands.ignored;
    stats.malformed = commands.malformed;
  }
  stats.max_commands_per_s = config_.max_commands_per_s;
  stats.commands_delayed = commands_delayed_;
  return stats;
}

std::optional<StoreStats> EdgeNode::store_stats() const {
  if (!backlog_) return std::nullopt;
  const BacklogCounts counts = backlog_->counts();
  return StoreStats{"sparkplug",     counts.bytes,    counts.records,
                    counts.dropped, counts.replayed, counts.lost};
}

}  // namespace tiltgate::sparkplug
