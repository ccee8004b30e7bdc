// One configured sensor as the gateway core holds it: its driver (and through it the cache),
// what is derived from each of its readings, its register map, the holding-register values
// written through the gateway, and the snapshot of all that the Modbus TCP threads read.
//
// Threads: driver, processing, written, bus, line_time and quiet_until belong to the bus's
// thread (the event loop); config, map and stale_after do not change while the sensor is served; the TCP
// threads read only those and snapshot(). Its last owner may be a request on a TCP thread (a reload dropped
// it meanwhile): it holds no I/O objects, so it may be freed there.
#pragma once

#include <chrono>
#include <memory>
#include <vector>

#include "config/config.h"
#include "driver/family.h"
#include "driver/sensor_driver.h"
#include "line_scheduling/sensor_feed.h"
#include "line_scheduling/sensor_processing.h"
#include "line_scheduling/sensor_snapshot.h"
#include "mapping/map_access.h"
#include "mapping/register_map.h"

namespace tiltgate {

class BusScheduler;

struct GatewaySensor {
  SensorConfig config;
  // Its model as its family describes it (identity, register 37), resolved once when the
  // sensor is made: a read never looks a model up by name.
  const ModelDescriptor* model = nullptr;
  std::unique_ptr<SensorDriver> driver;
  // Mounting, tilt and alarms of the latest reading. BusScheduler::add() builds it from
  // config.mounting and config.alarms, and updates it after every poll that brought a new
  // reading (processed_seq is the driver's sample_seq it last saw).
  SensorProcessing processing{MountingConfig{}, AlarmConfig{}};
  std::uint16_t processed_seq = 0;
  // The baseline it starts with: [[sensor]] baseline, or the one set since (the gateway's
  // baseline book, monitoring/baseline_book.h). Later changes go to processing directly.
  Baseline baseline;
  // Every processed reading and alarm change, for the monitoring (line_scheduling/sensor_feed.h).
  std::shared_ptr<SensorFeed> feed = std::make_shared<SensorFeed>();
  RegisterMap map;
  // Holding shadow, sized to map.holding_end(): what was written through the gateway, kept by
  // SensorWrite (line_scheduling/sensor_write.h).
  std::vector<std::uint16_t> written;
  std::chrono::milliseconds stale_after{1000};
  // The bus that polls it, kept alive by it: a write on its way holds the sensor, and through
  // it the bus, however a reload changed things meanwhile (the gateway frees a replaced bus
  // once nothing holds it, on its own thread: Gateway::free_unused_buses()).
  std::shared_ptr<BusScheduler> bus;
  // The line's time its polls, writes and retries took, waiting for replies, time-outs and
  // late-reply guards included (BusScheduler): who eats the line.
  std::chrono::nanoseconds line_time{0};
  // A late reply of the sensor may still come until then (the line was given to others before
  // its late-reply window closed, line_scheduling/line_claimant.h): nothing is sent to it before.
  SteadyClock::time_point quiet_until{};
  // Its bus listens to the active gateway of a redundant pair (BusScheduler::listen_to()):
  // published as SensorState::standby.
  bool standby = false;

  // Bus thread: copies state, derived values and written registers into a new snapshot, after
  // anything changed them (a poll, a write, a moved address).
  void publish() {
    auto snapshot = std::make_shared<SensorSnapshot>(
        SensorSnapshot{driver->state(), processing.derived(), written});
    snapshot->state.standby = standby;
    published.publish(std::move(snapshot));
  }
  // Any thread: the latest published snapshot (the first is published by BusScheduler::add()).
  std::shared_ptr<const SensorSnapshot> snapshot() const { return published.get(); }
  // The same, while `instant` holds every sensor's snapshot still.
  std::shared_ptr<const SensorSnapshot> snapshot(const SnapshotSlot::Instant& instant) const {
    return published.get(instant);
  }

  // What the register map reads of `snapshot`, which the caller keeps alive.
  SensorView view(const SensorSnapshot& snapshot, SteadyClock::time_point now,
                  WordOrder order) const {
    SensorView view{snapshot.state, now, stale_after, snapshot.written, order};
    view.derived = &snapshot.derived;
    view.offline = config.offline;
    view.substitute = config.substitute;
    view.model_code = model != nullptr ? model->model_code : 0;
    return view;
  }

  SnapshotSlot published;
};

// The default: three missed polls, but never less than a second, so a 20 Hz poll does not
// flag stale on one late reply.
inline std::chrono::milliseconds default_stale_after(std::chrono::milliseconds poll) {
  return std::max(3 * poll, std::chrono::milliseconds(1000));
}

}  // namespace tiltgate
