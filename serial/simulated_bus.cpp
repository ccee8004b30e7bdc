#include "serial/simulated_bus.h"

namespace tiltgate {

void use_setup(const SimulatorSetup& setup, SimulatedBusOptions& options) {
  options.link_path = setup.link;
  if (setup.pace_baud > 0) options.pace_baud = setup.pace_baud;
  if (setup.listen_baud > 0) options.listen_baud = setup.listen_baud;
}

SimulatedBus::SimulatedBus(boost::asio::io_context& io, const SimulatedBusOptions& options,
                           unsigned bits_per_byte)
    : reply_latency_(options.reply_latency),
      made_(std::chrono::steady_clock::now()),
      server_(io,
              PtyBusServerOptions{options.link_path, options.pace_baud, bits_per_byte,
                                  options.listen_baud},
              [this](std::span<const std::uint8_t> bytes) {
                counters_.bytes_received += bytes.size();
                receive(bytes);
              },
              [this] { ++counters_.replies_sent; }) {}

// Unplugged before the family's members go: no handler of the port reaches them after.
SimulatedBus::~SimulatedBus() { stop(); }

Expected<Done, std::string> SimulatedBus::start() {
  server_.unplug();  // before the framing is replaced: no handler of the old port feeds it
  reset_framing();
  return server_.start();
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
