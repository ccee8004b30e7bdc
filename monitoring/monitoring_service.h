// The monitoring (docs/monitoring.md) as a service attached to the gateway
// (gateway/gateway_service.h): what becomes of each sensor's readings beyond the registers.
//
// Every kTick, on the gateway's event loop, it takes each sensor's feed (the readings and alarm
// changes its bus put there, line_scheduling/sensor_feed.h) and looks at its snapshot (online,
// wrong device), and turns what changed into events (monitoring/event_record.h). The disk is
// its own thread's business (the event log, monitoring/event_log.h), so neither a line nor a
// Modbus reply ever waits for it.
//
// Baselines: the stored ones (monitoring/baseline_book.h) are given to the sensors when they
// are made (at start, at each reload: Gateway::baselines_from()); set_baseline() changes one
// at once, keeps it, audits it and records an event.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/thread_pool.hpp>
#include <chrono>
#include <map>
#include <mutex>
#include <set>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "audit/audit_trail.h"
#include "driver/expected.h"
#include "gateway/gateway.h"
#include "gateway/gateway_service.h"
#include "monitoring/baseline_book.h"
#include "monitoring/burst_feed.h"
#include "monitoring/burst_recorder.h"
#include "monitoring/interval_summary.h"
#include "monitoring/long_record.h"
#include "store/file_io.h"
#include "monitoring/event_log.h"

namespace tiltgate::monitoring {

inline constexpr std::chrono::milliseconds kTick{200};

// What set_baseline() is asked: a reading (x, y), or the sensor's current one, or none (the
// stored baseline cleared: the configuration's applies again).
struct BaselineChange {
  enum class Kind { value, current, clear };
  Kind kind = Kind::current;
  Baseline value;
};

class MonitoringService final : public GatewayService {
 public:
  MonitoringService(Gateway& gateway, AuditTrail& audit);
  ~MonitoringService() override;

  void start() override {}
  // The event log and the baseline book in <state_dir> (the serving user's files), and the
  // timer.
  void start_as_user() override;
  bool reload(const Config& loaded, const ConfigDiff& diff) override;
  void stop() override;
  std::string_view name() const override { return "monitoring"; }

  // Any thread: the events kept, newest first; those after `seq`, oldest first (the MQTT
  // topic's, at most `max`).
  std::vector<EventRecord> events(const EventQuery& query) const;
  std::vector<EventRecord> events_after(std::uint64_t seq, std::size_t max) const;
  std::uint64_t last_event_seq() const;
  // Where a sensor's burst records are (monitoring/burst_files.h); empty without a state
  // directory. Any thread.
  std::filesystem::path bursts_of(const std::string& sensor) const;
  // Whether `sensor` is configured now. Any thread.
  bool serves(const std::string& sensor) const;
  // Where a sensor's long record is (monitoring/long_record.h); empty without a state
  // directory. Any thread.
  std::filesystem::path record_of(const std::string& sensor) const;
  // The bursts' samples as they are recorded, for the feeds (monitoring/burst_feed.h).
  const BurstFeed& burst_feed() const { return burst_feed_; }

  // The gateway's executor: the sensor's baseline changed as asked, kept in the book,
  // audited (door and who from `by`) and recorded as an event. The error says why not (no
  // such sensor, no reading for "current", a disk that refuses the book).
  Expected<StoredBaseline, std::string> set_baseline(const std::string& sensor,
                                                     const BaselineChange& change,
                                                     const WriteOrigin& by);
  // Any thread: the baseline a sensor has now, and whether it was set since the configuration.
  struct BaselineNow {
    Baseline baseline;
    std::optional<StoredBaseline> stored;
  };
  std::optional<BaselineNow> baseline(const std::string& sensor) const;

 private:
  struct Watched {
    std::optional<bool> online;  // unknown until the sensor answered or failed to
    bool wrong_device = false;
    std::optional<BurstRecorder> bursts;  // made with the sensor's config (remade at a reload)
    SensorConfig burst_config;            // what `bursts` was made with
    std::filesystem::path burst_file;     // the running burst's; empty: none
    std::string burst_id;                 // the running burst's; empty: none
    std::optional<IntervalSummary> summary;  // the long record's open interval
  };

  void schedule();
  void tick();
  void watch(const GatewaySensor& sensor, std::vector<EventRecord>& events);
  // The sensor's bursts: started (its bus polls it fast), written as they go, ended.
  void record_bursts(GatewaySensor& sensor, const FedBatch& batch, std::vector<EventRecord>& events);
  // Events to the disk's thread: kept, synced, logged.
  void keep(std::vector<EventRecord> events);

  Gateway& gateway_;
  AuditTrail& audit_;
  std::shared_ptr<EventLog> log_;  // made at start_as_user(); the disk thread writes it
  std::shared_ptr<EventLog> event_log() const;  // log_, from any thread
  std::shared_ptr<BaselineBook> book_;
  // [server] state_dir, where the records and bursts are kept; empty: none kept.
  std::filesystem::path state_dir_;
  BurstFeed burst_feed_;
  // This gateway holds <state_dir>/events/lock: the files above are its own to write.
  bool keeps_files_ = false;
  store::UniqueFd lock_;
  RecordConfig record_config_;
  // Each sensor's long record, by name: the disk thread appends; start and reloads open them.
  std::mutex records_mutex_;
  std::map<std::string, LongRecord> records_;
  std::chrono::steady_clock::time_point expired_at_{};  // the last retention pass
  std::map<std::string, Watched> watched_;  // by sensor name; the event loop's
  void note_sensors();  // names_ from the gateway's sensors, at start and each reload
  // The long record: each sensor's open interval fed its samples; what closes goes to the
  // disk's thread. open_records(): a record for each sensor without one (start, reload).
  void summarise(const GatewaySensor& sensor, const FedBatch& batch, std::int64_t now_unix_ms);
  void open_records();
  mutable std::mutex names_mutex_;  // names_, and log_ as the pointer it is
  std::set<std::string> names_;
  boost::asio::steady_timer timer_;
  boost::asio::thread_pool disk_{1};
  bool running_ = false;
};

}  // namespace tiltgate::monitoring
