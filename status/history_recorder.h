// Every sensor's angle history (status/angle_history.h), filled from the status snapshots the
// gateway takes on a timer: the same copy /api/sensors shows, so the graph and the live values
// agree. Pure: the gateway calls record() on its event loop, the HTTP routes call history().
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "status/angle_history.h"
#include "gateway/gateway_status.h"

namespace tiltgate {

class HistoryRecorder {
 public:
  // One ring of `samples_per_sensor` for each of `sensor_names`, memory taken now; those
  // also named in `with_temperature` (sensors that report one) keep the temperature too.
  HistoryRecorder(std::vector<std::string> sensor_names, std::size_t samples_per_sensor,
                  const std::vector<std::string>& with_temperature = {});

  // One sample per sensor of `status` taken at `unix_ms`. A sensor without a fresh reading
  // (none yet, or stale) gets a sample without angles: a gap in its graph, not an old value
  // drawn as if it were current. Sensors not named at construction are ignored.
  void record(const GatewayStatus& status, std::int64_t unix_ms);

  // Takes the rings of the sensors `previous` has too (same name, same number of samples, a
  // temperature or none in both): a reload keeps the graphs of its sensors that keep their name.
  void carry_over(const HistoryRecorder& previous);

  // The sensor's samples, oldest first; none for a name not configured.
  std::optional<std::vector<AngleSample>> history(std::string_view sensor) const;

 private:
  std::vector<std::string> names_;
  std::vector<AngleRing> rings_;  // rings_[i] is names_[i]'s
};

}  // namespace tiltgate
