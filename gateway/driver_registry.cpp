#include "gateway/driver_registry.h"

#include "rieker/rieker_driver.h"

namespace tiltgate {

std::unique_ptr<SensorDriver> make_driver(const SensorConfig& sensor, const BusConfig& bus) {
  if (bus.protocol == BusProtocol::rieker && (sensor.model == "h6" || sensor.model == "h4360")) {
    rieker::RiekerDriverOptions options;
    options.name = sensor.name;
    options.model = sensor.model == "h6" ? rieker::Model::h6 : rieker::Model::h4360;
    options.address = std::uint16_t(sensor.address);
    options.master_address = bus.master_address;
    return std::make_unique<rieker::RiekerDriver>(options);
  }
  return nullptr;
}

}  // namespace tiltgate
