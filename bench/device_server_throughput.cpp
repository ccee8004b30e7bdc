// What a serial device server costs a Rieker bus: polls/s of the gateway's own line and driver
// (SerialLine + RiekerDriver, Get Angle back to back) against one simulated H6 at 250000 baud,
// the highest Rieker rate Debian's ser2net sets on a pseudo-terminal, reached three ways in
// one run, side by side (each round measures every way in turn, the order turning each round):
//   local pty      the simulator's pseudo-terminal opened as a tty, the reference;
//   ser2net raw    `port = "tcp://..."` to ser2net serving that pty (connector 250000n81,local);
//                  once with ser2net's defaults, once with `chardelay: false` (ser2net then
//                  forwards what the device sent at once instead of waiting for a pause);
//   + 2 ms         the same, chardelay off, through a relay adding 1 ms each way
//                  (bench/tcp_delay_relay.h), against the figure docs/performance.md's formula
//                  predicts: per poll, the local pty's poll time plus the round trip.
// The simulator paces its replies at the baud rate and answers with no latency of its own, as
// in bench/bus_throughput.cpp. Prints medians of the rounds and their ratios.
// Usage: bench_device_server_throughput [rounds] [seconds-per-run]
#include <algorithm>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <spawn.h>
#include <memory>
#include <spdlog/spdlog.h>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include "bench/tcp_delay_relay.h"
#include "device_server/serial_line_maker.h"
#include "rieker/rieker_driver.h"
#include "rieker/simulator.h"
#include "serial/serial_line.h"

extern char** environ;

using namespace tiltgate;
using namespace std::chrono;

namespace {

constexpr std::uint32_t kBaud = 250000;
constexpr microseconds kOneWay{1000};  // the relay's delay each way: a 2 ms round trip

enum class Way { local_pty, ser2net_defaults, ser2net, ser2net_plus_2ms };

std::uint16_t free_port() {
  boost::asio::io_context io;
  boost::asio::ip::tcp::acceptor a(io, {boost::asio::ip::address_v4::loopback(), 0});
  return a.local_endpoint().port();
}

// ser2net in the foreground on 127.0.0.1:port serving `device`; killed when it goes.
class Ser2net {
 public:
  Ser2net(const std::filesystem::path& dir, const std::string& device, bool chardelay)
      : port_(free_port()) {
    const auto config = dir / "ser2net.yaml";
    std::ofstream(config) << "connection: &bench\n  accepter: tcp,127.0.0.1," << port_
                          << "\n  connector: serialdev," << device << "," << kBaud
                          << "n81,local\n"
                          << (chardelay ? "" : "  options:\n    chardelay: false\n");
    const std::string path = config.string();
    const char* argv[] = {"ser2net", "-n", "-c", path.c_str(), nullptr};
    posix_spawn_file_actions_t quiet;
    posix_spawn_file_actions_init(&quiet);
    posix_spawn_file_actions_addopen(&quiet, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&quiet, 2, "/dev/null", O_WRONLY, 0);
    if (posix_spawnp(&pid_, "ser2net", &quiet, nullptr, const_cast<char**>(argv), environ) != 0)
      pid_ = -1;
    posix_spawn_file_actions_destroy(&quiet);
    // Listening about 20 ms after exec; a connect then would open the pty for nothing, so wait.
    std::this_thread::sleep_for(milliseconds(300));
  }
  ~Ser2net() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }
  Ser2net(const Ser2net&) = delete;
  Ser2net& operator=(const Ser2net&) = delete;
  bool running() const { return pid_ > 0; }
  std::uint16_t port() const { return port_; }

 private:
  std::uint16_t port_;
  pid_t pid_ = -1;
};

// Polls/s of Get Angle back to back over `port` for run_time, after the first good poll.
double polls_per_second(boost::asio::io_context& io, const std::string& port, seconds run_time) {
  SerialLineOptions line_options;
  line_options.name = "bench";
  line_options.port = port;
  line_options.baud = kBaud;
  line_options.timeout = milliseconds(200);
  line_options.reopen_min = milliseconds(50);
  line_options.replies_name_sender = true;
  // Made as the gateway makes a bus's line: a tty or a device server's port, from the port.
  const std::unique_ptr<SerialLine> made = make_serial_line(io.get_executor(), line_options);
  SerialLine& line = *made;
  line.start();
  rieker::RiekerDriverOptions driver_options;
  driver_options.reply_timeouts = {line_options.timeout, line_options.timeout};
  rieker::RiekerDriver driver(driver_options);

  std::uint32_t polls_at_start = 0;
  steady_clock::time_point start;
  bool done = false;
  bool answered = false;
  auto loop = [&]() -> boost::asio::awaitable<void> {
    // Connect, and the identity: not part of the measurement.
    const auto give_up = steady_clock::now() + seconds(5);
    while (!driver.state().online && steady_clock::now() < give_up) co_await driver.poll(line);
    answered = driver.state().online;
    start = steady_clock::now();
    polls_at_start = driver.state().counters.polls_ok;
    while (answered && steady_clock::now() - start < run_time) co_await driver.poll(line);
    done = true;
  };
  boost::asio::co_spawn(io, loop(), boost::asio::detached);
  while (!done) io.run_one_for(milliseconds(100));
  const double elapsed = duration<double>(steady_clock::now() - start).count();
  const double polls = driver.state().counters.polls_ok - polls_at_start;
  line.stop();
  io.run_for(milliseconds(10));
  return answered ? polls / elapsed : 0;
}

double measure(Way way, seconds run_time) {
  boost::asio::io_context io;
  char tmpl[] = "/tmp/tiltgate-bench-XXXXXX";
  const std::filesystem::path dir = ::mkdtemp(tmpl);
  rieker::RiekerSimulatorOptions sim_options;
  sim_options.sensors = {rieker::SimulatedSensorOptions{}};
  sim_options.pace_baud = kBaud;
  sim_options.reply_latency = microseconds(0);
  sim_options.link_path = (dir / "tty").string();
  rieker::RiekerSimulator sim(io, sim_options);
  double result = 0;
  if (sim.start()) {
    if (way == Way::local_pty) {
      result = polls_per_second(io, sim_options.link_path, run_time);
    } else {
      Ser2net server(dir, sim_options.link_path, way == Way::ser2net_defaults);
      std::optional<bench::TcpDelayRelay> relay;
      std::uint16_t port = server.port();
      if (way == Way::ser2net_plus_2ms) port = relay.emplace(server.port(), kOneWay).port();
      if (server.running())
        result = polls_per_second(io, "tcp://127.0.0.1:" + std::to_string(port), run_time);
    }
  }
  sim.stop();
  io.run_for(milliseconds(10));
  std::filesystem::remove_all(dir);
  return result;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  const int rounds = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const seconds run_time(argc > 2 ? std::max(1, std::atoi(argv[2])) : 2);
  const Way ways[] = {Way::local_pty, Way::ser2net, Way::ser2net_defaults, Way::ser2net_plus_2ms};
  std::vector<double> samples[4];
  for (int round = 0; round < rounds; ++round) {
    for (int i = 0; i < 4; ++i) {
      const int w = (round % 2 == 0) ? i : 3 - i;  // the order turns every round
      samples[w].push_back(measure(ways[w], run_time));
    }
  }
  const double local = median(samples[0]);
  const double round_trip = 2 * duration<double>(kOneWay).count();
  const double predicted = 1.0 / (1.0 / local + round_trip);
  std::printf("Rieker bus behind Debian's ser2net: one H6 at %u baud, Get Angle back to back, "
              "%d rounds of %llds per way, side by side\n\n",
              kBaud, rounds, static_cast<long long>(run_time.count()));
  std::printf("| way | median polls/s | min | max | per poll (us) | ratio to local pty | "
              "predicted polls/s | ratio to predicted |\n");
  std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  const char* names[] = {"local pty", "ser2net raw, chardelay off",
                         "ser2net raw, defaults (chardelay on)",
                         "ser2net raw, chardelay off, + 2 ms round trip"};
  for (int w = 0; w < 4; ++w) {
    auto sorted = samples[w];
    std::sort(sorted.begin(), sorted.end());
    const double m = median(samples[w]);
    std::printf("| %s | %.1f | %.1f | %.1f | %.0f | %.3f | ", names[w], m, sorted.front(),
                sorted.back(), m > 0 ? 1e6 / m : 0.0, local > 0 ? m / local : 0.0);
    if (ways[w] == Way::ser2net_plus_2ms)
      std::printf("%.1f | %.3f |\n", predicted, predicted > 0 ? m / predicted : 0.0);
    else
      std::printf("- | - |\n");
  }
  return 0;
}
