#include "modbus_rtu/simulator/simulator.h"

namespace tiltgate::modbus_rtu {

RtuSimulator::RtuSimulator(boost::asio::io_context& io, RtuSimulatorOptions options)
    : SimulatedBus(io, options, options.bits_per_byte), options_(std::move(options)) {}

SimulatedDevice* RtuSimulator::device(std::uint8_t slave) {
  for (SimulatedDevice& device : options_.devices)
    if (device.slave() == slave) return &device;
  return nullptr;
}

RtuSimulatorCounters RtuSimulator::counters() const {
  RtuSimulatorCounters own;
  own.crc_errors = crc_errors_;
  return with_bus_counters(own);
}

void RtuSimulator::receive(std::span<const std::uint8_t> bytes) {
  const std::uint64_t crc_errors_before = parser_.counters().crc_errors;
  parser_.feed(bytes);
  crc_errors_ += parser_.counters().crc_errors - crc_errors_before;
  while (auto request = parser_.next()) {
    count_request();
    // A slave that sees a bad CRC stays silent (Serial Line 2.4.1), so only good frames reach
    // the devices. Two that answer one request collide: the first reply stands, its CRC broken.
    Answers answers;
    for (SimulatedDevice& device : options_.devices) {
      if (options_.before_request) options_.before_request(device);
      if (auto reply = device.respond(*request)) answers.add(std::move(reply->frame), reply->delay);
    }
    send(std::move(answers));
  }
}

}  // namespace tiltgate::modbus_rtu
