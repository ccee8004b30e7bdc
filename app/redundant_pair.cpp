#include "app/redundant_pair.h"

#include <spdlog/spdlog.h>

#include <algorithm>

#include "config/redundancy_warnings.h"
#include "driver/visible_text.h"
#include "gateway/serial_options.h"

namespace tiltgate {

namespace {

// The first sensor's unit, on the listener its bus is served on: what the peer is asked about.
PeerProbe peer_probe_of(const Config& config) {
  PeerProbe probe;
  probe.host = config.redundancy.peer_host;
  probe.port = config.redundancy.peer_port;
  // Asked within takeover_ms (RedundancyController::silence_needed()): a quarter of it at most.
  probe.timeout = std::min(std::chrono::milliseconds{500}, config.redundancy.takeover / 4);
  if (config.sensors.empty()) return probe;
  const SensorConfig& sensor = config.sensors.front();
  probe.unit_id = sensor.unit_id;
  probe.has_unit = true;
  for (const BusConfig& bus : config.buses)
    if (bus.name == sensor.bus && bus.tcp_port) probe.port = *bus.tcp_port;
  return probe;
}

RedundantBus redundant_bus(FamilyList families, const BusConfig& bus, SerialLine& line,
                           BusScheduler& scheduler) {
  RedundantBus redundant;
  redundant.name = bus.name;
  redundant.line = &line;
  redundant.scheduler = &scheduler;
  const SerialLineOptions options = serial_options_from(families, bus);
  const int bits = bits_per_byte(idle_parity(options.framing), stop_bits_of(options.framing));
  if (options.baud > 0)
    redundant.character_time =
        std::chrono::nanoseconds(std::int64_t(bits) * 1'000'000'000 / std::int64_t(options.baud));
  const ProtocolEntry protocol = find_protocol(families, bus.protocol);
  // A device server's port takes one client: nothing to listen to there.
  if (bus.port.find("://") == std::string::npos && protocol.protocol != nullptr &&
      protocol.protocol->passive_framer != nullptr) {
    LineListenerOptions listening;
    listening.path = bus.port;
    listening.baud = options.baud;
    listening.framing = options.framing;
    listening.framer = protocol.protocol->passive_framer;
    redundant.listening = listening;
  }
  return redundant;
}

}  // namespace

std::unique_ptr<RedundancyController> make_redundant_pair(boost::asio::any_io_executor executor,
                                                          const Config& config,
                                                          FamilyList families, Gateway& gateway) {
  if (!config.redundancy.enabled()) return nullptr;
  // What `tiltgate check` warns of, in the log too: a bus the standby cannot follow.
  for (const std::string& warning : redundancy_warnings(config, families))
    spdlog::warn("redundancy: {}", visible_text(warning));
  auto controller =
      std::make_unique<RedundancyController>(executor, config.redundancy, peer_probe_of(config));
  RedundancyController* pair = controller.get();
  Gateway::LineKeeper keeper;
  keeper.start = [pair, families](const BusConfig& bus, SerialLine& line, BusScheduler& scheduler) {
    pair->add_bus(redundant_bus(families, bus, line, scheduler));
  };
  keeper.retire = [pair](const BusScheduler& scheduler) { pair->remove_bus(&scheduler); };
  keeper.stop = [pair] { pair->stop(); };
  gateway.keep_lines_with(std::move(keeper));
  return controller;
}

}  // namespace tiltgate
