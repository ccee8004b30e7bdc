// One serial bus: the only owner of its Line. Polls each sensor at its poll period, runs queued
// writes ahead of polls, and backs off from sensors that do not answer so they cannot starve
// the others. Everything runs on the event loop thread; nothing here blocks.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <deque>
#include <memory>
#include <vector>

#include "driver/line.h"
#include "driver/sensor_driver.h"
#include "gateway/gateway_sensor.h"
#include "gateway/poll_schedule.h"

namespace tiltgate {

struct BusSchedulerStats {
  std::uint64_t polls = 0;
  std::uint64_t writes = 0;
  std::uint64_t writes_expired = 0;  // still queued at their deadline
};

class BusScheduler {
 public:
  BusScheduler(boost::asio::any_io_executor executor, Line& line, std::string name);

  void add(GatewaySensor& sensor);
  // Runs until stop(). Spawn it once.
  boost::asio::awaitable<void> run();
  void stop();

  // Queues a write ahead of every poll and waits for it. A write still queued when `deadline`
  // passes is dropped and answered busy; one already on the wire is always waited for (its
  // transactions are bounded by the bus time-outs).
  boost::asio::awaitable<WriteResult> write(GatewaySensor& sensor, WriteTarget target,
                                            double value, SteadyClock::time_point deadline);

  // Refuses (bad_value: Modbus 0x03) a write that would move `sensor` to the address another
  // sensor on this bus has now: both would answer it, the bus would collide, and moving one
  // back would move both. write() checks again when the write starts.
  WriteResult check_address_free(const GatewaySensor& sensor, WriteTarget target,
                                 double value) const;

  const std::string& name() const { return name_; }
  const BusSchedulerStats& stats() const { return stats_; }
  Line& line() { return line_; }

  // Longest wait between polls of an offline sensor (gateway/poll_schedule.h).
  static constexpr std::chrono::milliseconds max_backoff{5000};

 private:
  struct Polled {
    GatewaySensor* sensor;
    PollSchedule schedule;
  };
  struct PendingWrite {
    GatewaySensor* sensor;
    WriteTarget target;
    double value;
    bool started = false;
    std::optional<WriteResult> result;
    boost::asio::steady_timer done;  // cancelled when result is set
  };

  Polled* next_due();
  // Derives mounting, tilt and alarms once per new reading (a new sample_seq).
  static void process_new_reading(GatewaySensor& sensor);
  boost::asio::awaitable<void> run_write(std::shared_ptr<PendingWrite> pending);

  boost::asio::any_io_executor executor_;
  Line& line_;
  std::string name_;
  std::vector<Polled> sensors_;
  std::deque<std::shared_ptr<PendingWrite>> writes_;
  boost::asio::steady_timer wake_;
  bool stopping_ = false;
  BusSchedulerStats stats_;
};

}  // namespace tiltgate
