#include "modbus_rtu/simulator.h"

namespace tiltgate::modbus_rtu {

RtuSimulator::RtuSimulator(boost::asio::io_context& io, RtuSimulatorOptions options)
    : options_(std::move(options)),
      server_(io,
              PtyBusServerOptions{options_.link_path, options_.pace_baud, options_.bits_per_byte,
                                  options_.listen_baud},
              [this](std::span<const std::uint8_t> bytes) { on_bytes(bytes); },
              [this] { ++counters_.replies_sent; }) {}

RtuSimulator::~RtuSimulator() { stop(); }

Expected<Done, std::string> RtuSimulator::start() {
  server_.unplug();  // before the parser is replaced: no handler of the old port feeds it
  parser_ = RtuFrameParser{FrameKind::request};
  return server_.start();
}

SimulatedDevice* RtuSimulator::device(std::uint8_t slave) {
  for (SimulatedDevice& device : options_.devices)
    if (device.slave() == slave) return &device;
  return nullptr;
}

void RtuSimulator::on_bytes(std::span<const std::uint8_t> bytes) {
  counters_.bytes_received += bytes.size();
  const std::uint64_t crc_errors_before = parser_.counters().crc_errors;
  parser_.feed(bytes);
  counters_.crc_errors += parser_.counters().crc_errors - crc_errors_before;
  while (auto request = parser_.next()) {
    ++counters_.requests_seen;
    // A slave that sees a bad CRC stays silent (Serial Line 2.4.1), so only good frames reach
    // the devices.
    for (SimulatedDevice& device : options_.devices) {
      if (auto reply = device.respond(*request))
        server_.send_after(options_.reply_latency + reply->delay, std::move(reply->frame));
    }
  }
}

}  // namespace tiltgate::modbus_rtu
