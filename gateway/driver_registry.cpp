#include "gateway/driver_registry.h"

namespace tiltgate {

DriverSetup driver_setup(const SensorConfig& sensor, const BusConfig& bus) {
  DriverSetup setup;
  setup.name = sensor.name;
  setup.protocol = bus.protocol;
  setup.model = sensor.model;
  setup.address = sensor.address;
  setup.master_address = bus.master_address;
  setup.reply_timeouts = {bus.timeout, bus.max_timeout};
  setup.options = sensor.family_options;
  return setup;
}

std::unique_ptr<SensorDriver> make_driver(FamilyList families, const SensorConfig& sensor,
                                          const BusConfig& bus) {
  const DriverSetup setup = driver_setup(sensor, bus);
  const ModelEntry model = find_model(families, setup.model);
  const ProtocolEntry protocol = find_protocol(families, setup.protocol);
  if (model.family == nullptr || model.family != protocol.family) return nullptr;
  return model.family->make_driver(setup);
}

}  // namespace tiltgate
