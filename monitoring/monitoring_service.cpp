#include "monitoring/monitoring_service.h"

#include <boost/asio/post.hpp>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

#include "monitoring/burst_files.h"
#include "store/file_io.h"

namespace tiltgate::monitoring {

namespace {

std::int64_t unix_ms_now() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

EventRecord alarm_event(const std::string& sensor, const FedTransition& fed) {
  const AlarmTransition& t = fed.change;
  EventRecord e;
  e.unix_ms = fed.unix_ms;
  e.sensor = sensor;
  e.kind = "alarm";
  e.alarm = to_string(t.kind);
  e.level = to_string(t.level);
  e.state = t.set ? "set" : "clear";
  e.value = t.value;
  e.threshold = t.threshold;
  return e;
}

EventRecord sensor_event(const std::string& sensor, std::string kind, std::string state,
                         std::string text) {
  EventRecord e;
  e.unix_ms = unix_ms_now();
  e.sensor = sensor;
  e.kind = std::move(kind);
  e.state = std::move(state);
  e.text = std::move(text);
  return e;
}

// One line in the log for each event: an alarm at warning (danger: error), the rest at info.
void log_event(const EventRecord& e) {
  if (e.kind == "alarm") {
    const auto level = e.state == "clear" ? spdlog::level::info
                       : e.level == "danger" ? spdlog::level::err
                                             : spdlog::level::warn;
    spdlog::log(level, "{}: {} alarm {} {}: {:g} against {:g}", e.sensor, e.level, e.alarm,
                e.state, e.value.value_or(NAN), e.threshold.value_or(NAN));
  } else if (e.kind == "baseline") {
    spdlog::info("{}: baseline x {:g} y {:g} (was x {:g} y {:g}), by {}", e.sensor,
                 e.x.value_or(NAN), e.y.value_or(NAN), e.previous_x.value_or(NAN),
                 e.previous_y.value_or(NAN), e.by);
  }
  // offline, online and wrong_device are logged by the drivers already.
}

}  // namespace

MonitoringService::MonitoringService(Gateway& gateway, AuditTrail& audit)
    : gateway_(gateway), audit_(audit), timer_(gateway.executor()) {
  // Set once, here: the HTTP threads read them from the start ([server] state_dir is read at
  // start only).
  state_dir_ = gateway_.config().server.state_dir;
}

MonitoringService::~MonitoringService() { disk_.join(); }

void MonitoringService::start_as_user() {
  const std::string& state_dir = gateway_.config().server.state_dir;
  const std::filesystem::path dir = state_dir;
  // One gateway per folder, as for the audit trail: a second one given the same state_dir keeps
  // its events, baselines, bursts and long record in memory, and says so.
  keeps_files_ = false;
  if (!state_dir.empty()) {
    std::error_code ignored;
    std::filesystem::create_directories(dir / "events", ignored);
    auto lock = store::lock_directory(dir / "events");
    if (lock) {
      lock_ = std::move(*lock);
      keeps_files_ = true;
    } else {
      spdlog::warn("monitoring: {}: events, baselines, bursts and the long record are kept in "
                   "memory only", lock.error());
    }
  }
  auto log = std::make_shared<EventLog>(keeps_files_ ? dir / "events" : std::filesystem::path());
  for (const std::string& notice : log->take_notices()) spdlog::warn("{}", notice);
  {
    std::lock_guard lock(names_mutex_);  // the HTTP threads may ask already
    log_ = std::move(log);
  }
  book_ = std::make_shared<BaselineBook>(keeps_files_ ? dir : std::filesystem::path());
  record_config_ = gateway_.config().record;
  if (book_->load_error()) spdlog::error("baselines: {}", *book_->load_error());
  std::shared_ptr<BaselineBook> book = book_;
  gateway_.baselines_from([book](const SensorConfig& sensor) { return book->effective(sensor); });
  // The sensors made before the book was read (the gateway's construction) take theirs now,
  // before any reading: the buses run once the event loop does.
  for (const auto& sensor : gateway_.sensors()) {
    sensor->baseline = book_->effective(sensor->config);
    sensor->processing.set_baseline(sensor->baseline);
  }
  note_sensors();
  open_records();
  running_ = true;
  schedule();
}

std::filesystem::path MonitoringService::record_of(const std::string& sensor) const {
  return state_dir_.empty() ? std::filesystem::path() : record_directory(state_dir_, sensor);
}

void MonitoringService::open_records() {
  if (state_dir_.empty() || !keeps_files_) return;
  LongRecordOptions options;
  options.keep_days = record_config_.keep_days;
  std::lock_guard lock(records_mutex_);
  for (const auto& sensor : gateway_.sensors()) {
    const std::string& name = sensor->config.name;
    Watched& w = watched_[name];
    auto it = records_.find(name);
    if (it == records_.end()) {
      it = records_.emplace(name, LongRecord::open(record_of(name), options)).first;
      for (const std::string& repair : it->second.repairs())
        spdlog::warn("long record of {}: {}", name, repair);
    }
    const auto interval = std::chrono::duration_cast<std::chrono::milliseconds>(
        record_config_.interval);
    if (!w.summary || w.summary->interval() != interval)
      w.summary.emplace(interval, it->second.written_until());
  }
}

void MonitoringService::summarise(const GatewaySensor& sensor, const FedBatch& batch,
                                  std::int64_t now_unix_ms) {
  if (state_dir_.empty() || !keeps_files_) return;
  Watched& w = watched_[sensor.config.name];
  if (!w.summary) return;
  std::vector<IntervalRecord> closed;
  for (const FedSample& fed : batch.samples) {
    Sample sample{fed.unix_ms, fed.x, fed.y, fed.tilt, fed.temperature_c, fed.clock_synchronised};
    if (auto interval = w.summary->add(sample)) closed.push_back(*interval);
  }
  if (auto interval = w.summary->close_due(now_unix_ms)) closed.push_back(*interval);
  if (closed.empty()) return;
  boost::asio::post(disk_, [this, name = sensor.config.name, closed = std::move(closed)] {
    std::lock_guard lock(records_mutex_);
    const auto it = records_.find(name);
    if (it == records_.end()) return;
    for (const IntervalRecord& interval : closed) it->second.append(interval);
    for (const RecordNotice& notice : it->second.take_notices())
      spdlog::log(notice.problem ? spdlog::level::err : spdlog::level::info,
                  "long record of {}: {}", name, notice.text);
  });
}

void MonitoringService::note_sensors() {
  std::set<std::string> names;
  for (const auto& sensor : gateway_.sensors()) names.insert(sensor->config.name);
  std::lock_guard lock(names_mutex_);
  names_ = std::move(names);
}

bool MonitoringService::serves(const std::string& sensor) const {
  std::lock_guard lock(names_mutex_);
  return names_.count(sensor) > 0;
}

bool MonitoringService::reload(const Config& loaded, const ConfigDiff&) {
  // Sensors a reload made found their baselines through Gateway::baselines_from(); those it
  // removed are no longer watched.
  std::map<std::string, Watched> kept;
  for (const auto& sensor : gateway_.sensors()) {
    const auto it = watched_.find(sensor->config.name);
    if (it != watched_.end()) kept.insert(*it);
  }
  watched_ = std::move(kept);
  note_sensors();
  const bool record_changed = !(loaded.record == record_config_);
  record_config_ = loaded.record;
  if (record_changed) {
    // Every open interval is kept as it stands, and the records take the new keep_days (a
    // rare change: written here, not on the disk's thread).
    std::lock_guard lock(records_mutex_);
    for (auto& [name, w] : watched_) {
      const auto interval = w.summary ? w.summary->close_now() : std::nullopt;
      const auto it = records_.find(name);
      if (interval && it != records_.end()) it->second.append(*interval);
      w.summary.reset();
    }
    records_.clear();
  }
  {
    // Records of sensors no longer served are closed (synced by their destructor).
    std::lock_guard lock(records_mutex_);
    for (auto it = records_.begin(); it != records_.end();)
      it = watched_.count(it->first) ? std::next(it) : records_.erase(it);
  }
  open_records();
  return false;
}

void MonitoringService::stop() {
  if (!running_) return;
  running_ = false;
  timer_.cancel();
  tick();  // what the buses put last
  // The open intervals are kept as they stand: a clean stop loses no sample of the record.
  for (auto& [name, w] : watched_) {
    if (!w.summary) continue;
    if (auto interval = w.summary->close_now()) {
      boost::asio::post(disk_, [this, name = name, interval = *interval] {
        std::lock_guard lock(records_mutex_);
        if (const auto it = records_.find(name); it != records_.end()) it->second.append(interval);
      });
    }
  }
  disk_.join();
  if (log_) log_->sync();
  std::lock_guard lock(records_mutex_);
  for (auto& [name, record] : records_) record.sync();
}

void MonitoringService::schedule() {
  timer_.expires_after(kTick);
  timer_.async_wait([this](const boost::system::error_code& error) {
    if (error || !running_) return;
    tick();
    schedule();
  });
}

void MonitoringService::tick() {
  std::vector<EventRecord> events;
  const std::int64_t now_unix_ms = unix_ms_now();
  for (const auto& sensor : gateway_.sensors()) {
    FedBatch batch = sensor->feed->take();
    for (const FedTransition& fed : batch.transitions)
      events.push_back(alarm_event(sensor->config.name, fed));
    if (batch.dropped > 0)
      spdlog::warn("{}: the monitoring fell behind: {} readings or alarm changes not seen",
                   sensor->config.name, batch.dropped);
    watch(*sensor, events);
    record_bursts(*sensor, batch, events);
    summarise(*sensor, batch, now_unix_ms);
  }
  // Once an hour: the days past keep_days go, and what was appended is synced (each record
  // also syncs every few appends itself).
  const auto now = std::chrono::steady_clock::now();
  if (now - expired_at_ >= std::chrono::hours(1)) {
    expired_at_ = now;
    boost::asio::post(disk_, [this, now_unix_ms] {
      std::lock_guard lock(records_mutex_);
      for (auto& [name, record] : records_) {
        record.sync();
        if (const std::size_t removed = record.remove_expired(now_unix_ms); removed > 0)
          spdlog::info("long record of {}: {} day(s) past keep_days removed", name, removed);
      }
    });
  }
  if (!events.empty()) keep(std::move(events));
}

void MonitoringService::watch(const GatewaySensor& sensor, std::vector<EventRecord>& events) {
  const std::shared_ptr<const SensorSnapshot> snapshot = sensor.snapshot();
  if (!snapshot) return;
  const SensorState& state = snapshot->state;
  Watched& w = watched_[sensor.config.name];
  const std::string& name = sensor.config.name;
  // Online once it answered; offline once it failed to (not merely not asked yet).
  std::optional<bool> online;
  if (state.online) online = true;
  else if (known_offline(state)) online = false;
  if (online && online != w.online) {
    events.push_back(*online ? sensor_event(name, "online", "", "the sensor answers")
                             : sensor_event(name, "offline", "", "the sensor stopped answering"));
    w.online = online;
  }
  if (state.wrong_device != w.wrong_device) {
    events.push_back(sensor_event(
        name, "wrong_device", state.wrong_device ? "set" : "clear",
        state.wrong_device
            ? fmt::format("serial {} answers, not the configured {}", state.serial,
                          sensor.config.serial)
            : fmt::format("the configured serial {} answers again", sensor.config.serial)));
    w.wrong_device = state.wrong_device;
  }
}

std::filesystem::path MonitoringService::bursts_of(const std::string& sensor) const {
  return state_dir_.empty() ? std::filesystem::path() : burst_directory(state_dir_, sensor);
}

void MonitoringService::record_bursts(GatewaySensor& sensor, const FedBatch& batch,
                                      std::vector<EventRecord>& events) {
  Watched& w = watched_[sensor.config.name];
  const SensorConfig& config = sensor.config;
  if (!w.bursts || w.burst_config.burst != config.burst ||
      w.burst_config.pre_trigger != config.pre_trigger ||
      w.burst_config.burst_rate_deg_s != config.burst_rate_deg_s) {
    w.bursts.emplace(config);
    w.burst_config = config;
    w.burst_file.clear();
    w.burst_id.clear();
  }
  BurstWork work = w.bursts->take(batch.samples, batch.transitions);
  std::string text;
  const std::string& name = config.name;
  // The same samples for the feeds (monitoring/burst_feed.h), a batch a phase.
  const auto publish = [&](const char* phase, std::vector<FedSample> samples) {
    burst_feed_.push(BurstBatch{0, name, w.burst_id, phase, std::move(samples)});
  };
  if (work.started) {
    if (sensor.bus) sensor.bus->burst(sensor, work.started->until);
    const std::string id = burst_id(work.started->unix_ms);
    w.burst_id = id;
    if (!state_dir_.empty() && keeps_files_) w.burst_file = bursts_of(name) / (id + ".csv");
    EventRecord e = sensor_event(name, "burst", "start", work.started->trigger);
    e.unix_ms = work.started->unix_ms;
    e.text = fmt::format("{}: polled as fast as the line allows for {} s; record {}",
                         work.started->trigger, config.burst.count(), id);
    events.push_back(std::move(e));
    text = burst_csv_header() + burst_csv_rows(work.started->pre, BurstPhase::pre);
    publish("pre", work.started->pre);
    if (!work.samples.empty()) {
      text += burst_csv_rows({work.samples.front()}, BurstPhase::trigger);
      publish("trigger", {work.samples.front()});
      work.samples.erase(work.samples.begin());
    }
  }
  text += burst_csv_rows(work.samples, BurstPhase::burst);
  if (!w.burst_id.empty()) publish("burst", work.samples);
  if (!w.burst_file.empty() && !text.empty()) {
    boost::asio::post(disk_, [file = w.burst_file, text = std::move(text),
                              dir = bursts_of(name), fresh = work.started.has_value()] {
      if (auto written = append_burst(file, text); !written)
        spdlog::error("burst record {}: {}", file.string(), written.error());
      if (fresh) remove_old_bursts(dir, kBurstsKept);
    });
  }
  if (work.ended) {
    events.push_back(sensor_event(name, "burst", "end", fmt::format("record {}", w.burst_id)));
    w.burst_file.clear();
    w.burst_id.clear();
  }
}

void MonitoringService::keep(std::vector<EventRecord> events) {
  boost::asio::post(disk_, [log = log_, events = std::move(events)]() mutable {
    if (!log) return;
    for (EventRecord& event : events) log_event(log->append(std::move(event)));
    log->sync();
    for (const std::string& notice : log->take_notices()) spdlog::warn("{}", notice);
  });
}

std::vector<EventRecord> MonitoringService::events(const EventQuery& query) const {
  const std::shared_ptr<EventLog> log = event_log();
  return log ? log->recent(query) : std::vector<EventRecord>{};
}

std::vector<EventRecord> MonitoringService::events_after(std::uint64_t seq,
                                                         std::size_t max) const {
  const std::shared_ptr<EventLog> log = event_log();
  return log ? log->after(seq, max) : std::vector<EventRecord>{};
}

std::shared_ptr<EventLog> MonitoringService::event_log() const {
  std::lock_guard lock(names_mutex_);
  return log_;
}

std::uint64_t MonitoringService::last_event_seq() const {
  const std::shared_ptr<EventLog> log = event_log();
  return log ? log->last_seq() : 0;
}

std::optional<MonitoringService::BaselineNow> MonitoringService::baseline(
    const std::string& sensor) const {
  for (const auto& s : gateway_.sensors())
    if (s->config.name == sensor) {
      BaselineNow now{s->processing.baseline(), {}};
      if (book_) now.stored = book_->find(sensor);
      return now;
    }
  return std::nullopt;
}

Expected<StoredBaseline, std::string> MonitoringService::set_baseline(
    const std::string& name, const BaselineChange& change, const WriteOrigin& by) {
  std::shared_ptr<GatewaySensor> sensor;
  for (const auto& s : gateway_.sensors())
    if (s->config.name == name) sensor = s;
  if (!sensor) return Unexpected(fmt::format("no sensor \"{}\"", name));
  if (!book_) return Unexpected(std::string("the monitoring has not started"));
  const Baseline before = sensor->processing.baseline();
  const std::string who = by.door + " " + by.who;
  const auto record = [&](const std::string& value, std::string result) {
    audit_.record({0, by, sensor->config.bus + "/" + name, "baseline",
                   fmt::format("x {:g} y {:g}", before.x, before.y), value, std::move(result)});
  };
  if (!audit_.accepts_changes()) {
    record("", std::string("refused: ") + std::string(kAuditRefusesChanges));
    return Unexpected(std::string(kAuditRefusesChanges));
  }
  Baseline next = change.value;
  std::optional<StoredBaseline> stored;
  if (change.kind == BaselineChange::Kind::current) {
    const DerivedState& d = sensor->processing.derived();
    const std::shared_ptr<const SensorSnapshot> snapshot = sensor->snapshot();
    if (!d.valid || !snapshot || !snapshot->state.reading) {
      record("current", "refused: no reading yet");
      return Unexpected(fmt::format("sensor \"{}\" has no reading to take as its baseline", name));
    }
    next = Baseline{d.angle_x, std::isnan(d.angle_y) ? 0.0 : d.angle_y};
  }
  if (change.kind == BaselineChange::Kind::clear) {
    next = sensor->config.baseline.value_or(Baseline{});
  } else {
    stored = StoredBaseline{next, unix_ms_now(), who};
  }
  const std::string value = change.kind == BaselineChange::Kind::clear
                                ? fmt::format("cleared: x {:g} y {:g} (the configuration's)",
                                              next.x, next.y)
                                : fmt::format("x {:g} y {:g}", next.x, next.y);
  if (auto written = book_->set(name, stored); !written) {
    record(value, "error: " + written.error());
    return Unexpected("the baseline could not be kept: " + written.error());
  }
  sensor->baseline = next;
  sensor->processing.set_baseline(next);
  sensor->publish();
  record(value, "ok");
  EventRecord e;
  e.unix_ms = unix_ms_now();
  e.sensor = name;
  e.kind = "baseline";
  e.x = next.x;
  e.y = next.y;
  e.previous_x = before.x;
  e.previous_y = before.y;
  e.by = who;
  if (change.kind == BaselineChange::Kind::clear) e.text = "set back to the configuration's";
  keep({e});
  return stored.value_or(StoredBaseline{next, e.unix_ms, who});
}

}  // namespace tiltgate::monitoring
