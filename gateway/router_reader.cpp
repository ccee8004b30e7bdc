#include "gateway/router_reader.h"

#include "modbus_tcp/modbus_request.h"

namespace tiltgate {

const UnitRoutes& RouterReader::routes() {
  // The generation first: the table then got is at least that new, so a table swapped in
  // between is taken at the next read.
  const std::uint64_t generation = router_.generation();
  if (routes_ == nullptr || generation != routes_generation_) {
    routes_ = router_.routes();
    routes_generation_ = generation;
    // The sensors kept may be the old table's, alive only through it.
    for (KeptSnapshot& kept : kept_) {
      kept.sensor = nullptr;
      kept.snapshot.reset();
    }
  }
  return *routes_;
}

RouterReader::KeptSnapshot& RouterReader::snapshot_of(const GatewaySensor& sensor,
                                                      std::uint8_t unit_id) {
  KeptSnapshot& kept = kept_[unit_id % kept_.size()];
  const std::uint64_t generation = sensor.published.generation();
  if (kept.sensor != &sensor || kept.generation != generation || kept.snapshot == nullptr) {
    kept.snapshot = sensor.snapshot();
    kept.sensor = &sensor;
    kept.generation = generation;
    kept.image.clear();
  }
  return kept;
}

bool RouterReader::passes_through(std::uint8_t unit_id) {
  return routes().forwarded[unit_id] != nullptr;
}

bool RouterReader::read(const ModbusRequest& request, ModbusResponse& response,
                        SteadyClock::time_point now) {
  const UnitRoutes& table = routes();
  const GatewaySensor* sensor = table.units[request.unit_id].get();
  if (sensor == nullptr) {
    scratch_.image = nullptr;
    return answer_from_cache(table, request, nullptr, now, response, scratch_);
  }
  KeptSnapshot& kept = snapshot_of(*sensor, request.unit_id);
  scratch_.image = &kept.image;
  return answer_from_cache(table, request, kept.snapshot.get(), now, response, scratch_);
}

}  // namespace tiltgate
