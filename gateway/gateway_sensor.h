// One configured sensor as the gateway core holds it: its driver (and through it the cache),
// what is derived from each of its readings, its register map, and the holding-register values
// written through the gateway.
#pragma once

#include <chrono>
#include <memory>
#include <vector>

#include "config/config.h"
#include "driver/sensor_driver.h"
#include "gateway/sensor_processing.h"
#include "mapping/map_access.h"
#include "mapping/register_map.h"

namespace tiltgate {

class BusScheduler;

struct GatewaySensor {
  SensorConfig config;
  std::unique_ptr<SensorDriver> driver;
  // Mounting, tilt and alarms of the latest reading. BusScheduler::add() builds it from
  // config.mounting and config.alarms, and updates it after every poll that brought a new
  // reading (processed_seq is the driver's sample_seq it last saw).
  SensorProcessing processing{MountingConfig{}, AlarmConfig{}};
  std::uint16_t processed_seq = 0;
  RegisterMap map;
  std::vector<std::uint16_t> written;  // holding shadow, sized to map.holding_end()
  std::chrono::milliseconds stale_after{1000};
  BusScheduler* bus = nullptr;

  SensorView view(SteadyClock::time_point now, WordOrder order) const {
    SensorView view{driver->state(), now, stale_after, written, order};
    view.derived = &processing.derived();
    view.offline = config.offline;
    view.substitute = config.substitute;
    view.model = driver->model();
    return view;
  }
};

// The default: three missed polls, but never less than a second, so a 20 Hz poll does not
// flag stale on one late reply.
inline std::chrono::milliseconds default_stale_after(std::chrono::milliseconds poll) {
  return std::max(3 * poll, std::chrono::milliseconds(1000));
}

}  // namespace tiltgate
