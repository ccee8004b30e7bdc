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
    std::optional<DeviceReply> first;
    std::size_t answering = 0;
    for (SimulatedDevice& device : options_.devices) {
      if (options_.before_request) options_.before_request(device);
      auto reply = device.respond(*request);
      if (reply && answering++ == 0) first = std::move(reply);
    }
    if (!first) continue;
    // Two devices that answer one request (two at one address) drive the bus at once: the
    // master receives one frame, garbled. The first reply stands for it, its CRC broken.
    if (answering > 1) {
      ++counters_.collisions;
      first->frame.back() ^= 0xFF;
    }
    server_.send_after(options_.reply_latency + first->delay, std::move(first->frame));
  }
}

}  // namespace tiltgate::modbus_rtu
