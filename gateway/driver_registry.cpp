#include "gateway/driver_registry.h"

#include "rieker/rieker_driver.h"
#include "spectron/dyna_driver.h"

namespace tiltgate {

namespace {

bool is_spectron(BusProtocol protocol) {
  return protocol == BusProtocol::spectron_9bit || protocol == BusProtocol::spectron_modbus;
}

ReplyTimeouts reply_timeouts_of(const BusConfig& bus) { return {bus.timeout, bus.max_timeout}; }

}  // namespace

std::unique_ptr<SensorDriver> make_driver(const SensorConfig& sensor, const BusConfig& bus) {
  if (bus.protocol == BusProtocol::rieker && (sensor.model == "h6" || sensor.model == "h4360")) {
    rieker::RiekerDriverOptions options;
    options.name = sensor.name;
    options.model = sensor.model == "h6" ? rieker::Model::h6 : rieker::Model::h4360;
    options.address = std::uint16_t(sensor.address);
    options.master_address = bus.master_address;
    options.reply_timeouts = reply_timeouts_of(bus);
    return std::make_unique<rieker::RiekerDriver>(options);
  }
  if (is_spectron(bus.protocol) && sensor.model == "dyna") {
    spectron::DynaDriverOptions options;
    options.name = sensor.name;
    options.protocol = bus.protocol == BusProtocol::spectron_9bit
                           ? spectron::Protocol::nine_bit
                           : spectron::Protocol::modbus_ascii;
    options.address = int(sensor.address);
    options.counts_per_degree = sensor.counts_per_degree;
    options.zero_counts = sensor.zero_counts;
    options.reply_timeouts = reply_timeouts_of(bus);
    options.reserved_writes = sensor.eeprom_reserved_writes;
    return std::make_unique<spectron::DynaDriver>(options);
  }
  return nullptr;
}

}  // namespace tiltgate
