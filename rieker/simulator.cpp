#include "rieker/simulator.h"

namespace tiltgate::rieker {
namespace {

constexpr unsigned kBitsPerByte = 10;  // 8N1: start + 8 data + stop

}  // namespace

RiekerSimulator::RiekerSimulator(boost::asio::io_context& io, RiekerSimulatorOptions options)
    : options_(std::move(options)),
      started_(std::chrono::steady_clock::now()),
      server_(io, PtyBusServerOptions{options_.link_path, options_.pace_baud, kBitsPerByte,
                                              options_.listen_baud},
              [this](std::span<const std::uint8_t> bytes) { on_bytes(bytes); },
              [this] { ++counters_.replies_sent; }) {
  sensors_.reserve(options_.sensors.size());
  for (const auto& sensor : options_.sensors) sensors_.emplace_back(sensor);
}

RiekerSimulator::~RiekerSimulator() { stop(); }

Expected<Done, std::string> RiekerSimulator::start() {
  server_.unplug();  // before the parser is replaced: no handler of the old port feeds it
  parser_ = RiekerFrameParser{};
  return server_.start();
}

SimulatedSensor* RiekerSimulator::sensor_by_address(std::uint16_t address) {
  for (auto& sensor : sensors_) {
    if (sensor.address() == address) return &sensor;
  }
  return nullptr;
}

void RiekerSimulator::on_bytes(std::span<const std::uint8_t> bytes) {
  counters_.bytes_received += bytes.size();
  const std::uint64_t crc_errors_before = parser_.counters().crc_errors;
  parser_.feed(bytes);
  counters_.crc_errors += parser_.counters().crc_errors - crc_errors_before;
  while (auto request = parser_.next()) dispatch(*request);
  const auto damaged = parser_.take_crc_failure();
  if (!damaged || !options_.nak_on_crc_failure) return;
  for (auto& sensor : sensors_) {
    if (auto reply = sensor.handle_crc_failure(*damaged)) queue_reply(encode(*reply));
  }
}

void RiekerSimulator::dispatch(const Frame& request) {
  ++counters_.requests_seen;
  const SimTime at = now();
  std::optional<std::vector<std::uint8_t>> reply;
  std::chrono::milliseconds delay{0};
  std::size_t answering = 0;
  for (auto& sensor : sensors_) {
    auto bytes = sensor.respond(request, at);
    if (!bytes) continue;
    if (++answering > 1) continue;
    reply = std::move(bytes);
    delay = sensor.reply_delay(request.function);
  }
  if (!reply) return;
  // Two sensors that answer one request (two at one address, or a broadcast query to several)
  // drive the bus at once: the master receives one frame, garbled. The first reply stands for
  // it, with its CRC broken.
  if (answering > 1) {
    ++counters_.collisions;
    reply->back() ^= 0xFF;
  }
  queue_reply(std::move(*reply), delay);
}

void RiekerSimulator::queue_reply(std::vector<std::uint8_t> bytes,
                                  std::chrono::milliseconds extra_delay) {
  server_.send_after(options_.reply_latency + extra_delay, std::move(bytes));
}

SimTime RiekerSimulator::now() const {
  return std::chrono::steady_clock::now() - started_;
}

}  // namespace tiltgate::rieker
