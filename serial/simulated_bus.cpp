#include "serial/simulated_bus.h"

#include <fmt/format.h>

namespace tiltgate {

void use_setup(const SimulatorSetup& setup, SimulatedBusOptions& options) {
  options.link_path = setup.link;
  if (setup.pace_baud > 0) options.pace_baud = setup.pace_baud;
  if (setup.listen_baud > 0) options.listen_baud = setup.listen_baud;
  if (!setup.second_master.empty()) options.second_master_link = setup.second_master;
  options.stats_path = setup.stats;
}

SimulatedBus::SimulatedBus(boost::asio::io_context& io, const SimulatedBusOptions& options,
                           unsigned bits_per_byte)
    : reply_latency_(options.reply_latency),
      made_(std::chrono::steady_clock::now()),
      server_(io,
              PtyBusServerOptions{options.link_path, options.pace_baud, bits_per_byte,
                                  options.listen_baud, options.second_master_link},
              [this](std::span<const std::uint8_t> bytes) {
                counters_.bytes_received += bytes.size();
                receive(bytes);
              },
              [this] { ++counters_.replies_sent; }, [this] { reset_framing(); }) {
  if (!options.stats_path.empty()) {
    stats_file_.emplace(io, options.stats_path, [this] { return line_stats(); });
  }
}

// Unplugged before the family's members go: no handler of the port reaches them after.
SimulatedBus::~SimulatedBus() { stop(); }

Expected<Done, std::string> SimulatedBus::start() {
  server_.stop();  // before the framing is replaced: no handler of the old ports feeds it
  reset_framing();
  if (auto started = server_.start(); !started) return started;
  if (stats_file_) {
    const auto written = stats_file_->start();
    if (!written) return Unexpected("--stats: " + written.error());
  }
  return Done{};
}

Expected<Done, std::string> SimulatedBus::replug(std::size_t master) {
  server_.unplug(master);
  reset_framing();
  return server_.replug(master);
}

std::optional<Expected<Done, std::string>> SimulatedBus::plug_command(
    const SimulatorCommand& command) {
  if (command.verb != "unplug" && command.verb != "replug") return std::nullopt;
  if (command.address < 1 || command.address > server_.masters() || !command.values.empty())
    return Unexpected{fmt::format("{} takes a master: 1{}", command.verb,
                                  server_.masters() > 1 ? " or 2" : "")};
  const std::size_t master = command.address - 1;
  if (command.verb == "replug") return replug(master);
  unplug(master);
  return Done{};
}

void SimulatedBus::stop() {
  if (stats_file_) stats_file_->stop();
  server_.stop();
}

SimulatedLineStats SimulatedBus::line_stats() const {
  SimulatedLineStats stats;
  for (std::size_t master = 0; master < server_.masters(); ++master) {
    const MasterCounters& counters = server_.master_counters(master);
    const std::string& link = server_.link_path(master);
    stats.masters.push_back(SimulatedMasterStats{link.empty() ? server_.slave_path(master) : link,
                                                 counters.bytes_sent, counters.bytes_received});
  }
  const PtyBusCounters line = server_.counters();
  // The line's collisions, and the requests several devices answered at once (one garbled
  // reply each): everything that arrived broken because two drove the line.
  stats.collisions = line.collisions + counters_.collisions;
  stats.master_collisions = line.master_collisions;
  stats.device_replies = line.sends_completed;
  return stats;
}

void SimulatedBus::garble(std::vector<std::uint8_t>& reply) const {
  if (!reply.empty()) reply.back() ^= 0xFF;
}

void SimulatedBus::Answers::add(std::vector<std::uint8_t> bytes, std::chrono::milliseconds delay) {
  if (count_++ > 0) return;
  first_ = std::move(bytes);
  delay_ = delay;
}

void SimulatedBus::send(Answers answers) {
  if (!answers.first_) return;
  if (answers.count_ > 1) {
    ++counters_.collisions;
    garble(*answers.first_);
  }
  send_reply(std::move(*answers.first_), answers.delay_);
}

void SimulatedBus::send_reply(std::vector<std::uint8_t> bytes,
                              std::chrono::milliseconds extra_delay) {
  server_.send_after(reply_latency_ + extra_delay, std::move(bytes));
}

}  // namespace tiltgate
