// How close the gateway runs a Rieker bus to the wire's own limit.
//
// A paced simulator (replies take their real wire time at the baud rate) answers a real
// SerialLine + RiekerDriver over a pseudo-terminal; the driver polls angles back to back for a
// fixed time. The reference is the wire limit: per poll, the request's bits at that baud, then
// the reply's bits or the manual's 1 ms between master packets, whichever is longer (at
// 250000 baud the reply is shorter than the gap). The simulated sensor answers with no latency of its
// own, so the gap between measured and limit is the gateway's own overhead per poll (pty,
// event loop, parsing). Prints medians of several runs and their ratio to the wire limit.
#include <algorithm>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <spdlog/spdlog.h>
#include <unistd.h>
#include <vector>

#include "rieker/rieker_driver.h"
#include "rieker/simulator.h"
#include "serial/serial_line.h"

using namespace tiltgate;
using namespace std::chrono;

namespace {

// Get Angle type 4: request 7 + 1 + 2 bytes, reply 7 + 8 + 2 bytes; 10 bits a byte (8N1).
constexpr double kRequestBytes = 10;
constexpr double kReplyBytes = 17;
constexpr double kGapSeconds = 0.001;

double wire_limit_polls_per_second(std::uint32_t baud) {
  const double request = kRequestBytes * 10.0 / baud;
  const double reply = kReplyBytes * 10.0 / baud;
  return 1.0 / (request + std::max(reply, kGapSeconds));
}

double measure_polls_per_second(std::uint32_t baud, seconds run_time) {
  boost::asio::io_context io;
  char tmpl[] = "/tmp/tiltgate-bench-XXXXXX";
  const std::filesystem::path dir = ::mkdtemp(tmpl);
  rieker::RiekerSimulatorOptions sim_options;
  rieker::SimulatedSensorOptions sensor;
  sim_options.sensors = {sensor};
  sim_options.pace_baud = baud;
  sim_options.reply_latency = microseconds(0);
  sim_options.link_path = (dir / "tty").string();
  rieker::RiekerSimulator sim(io, sim_options);
  if (!sim.start()) return 0;
  SerialLineOptions line_options;
  line_options.name = "bench";
  line_options.port = sim_options.link_path;
  line_options.baud = baud;
  line_options.timeout = milliseconds(200);
  SerialLine line(io.get_executor(), line_options);
  line.start();
  rieker::RiekerDriverOptions driver_options;
  driver_options.reply_timeouts = {line_options.timeout, line_options.timeout};  // drivers pass theirs
  rieker::RiekerDriver driver(driver_options);

  std::uint32_t polls_at_start = 0;
  steady_clock::time_point start;
  bool done = false;
  auto loop = [&]() -> boost::asio::awaitable<void> {
    co_await driver.poll(line);  // identity first: not part of the measurement
    start = steady_clock::now();
    polls_at_start = driver.state().counters.polls_ok;
    while (steady_clock::now() - start < run_time) co_await driver.poll(line);
    done = true;
  };
  boost::asio::co_spawn(io, loop(), boost::asio::detached);
  while (!done) io.run_one_for(milliseconds(100));
  const double elapsed = duration<double>(steady_clock::now() - start).count();
  const double polls = driver.state().counters.polls_ok - polls_at_start;
  line.stop();
  sim.stop();
  io.run_for(milliseconds(10));
  std::filesystem::remove_all(dir);
  return polls / elapsed;
}

}  // namespace

int main(int argc, char** argv) {
  spdlog::set_level(spdlog::level::warn);
  const int runs = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const seconds duration(argc > 2 ? std::max(1, std::atoi(argv[2])) : 2);
  std::printf("Rieker bus throughput: one H6, Get Angle polls back to back, %d runs of %llds\n\n",
              runs, static_cast<long long>(duration.count()));
  std::printf("| baud | wire limit (polls/s) | median measured (polls/s) | min | max | ratio | "
              "overhead per poll (us) |\n");
  std::printf("| ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  for (std::uint32_t baud : {9600u, 38400u, 125000u, 250000u}) {
    std::vector<double> samples;
    for (int i = 0; i < runs; ++i) samples.push_back(measure_polls_per_second(baud, duration));
    std::sort(samples.begin(), samples.end());
    const double median = samples[samples.size() / 2];
    const double limit = wire_limit_polls_per_second(baud);
      const double overhead_us = (1.0 / median - 1.0 / limit) * 1e6;
    std::printf("| %u | %.1f | %.1f | %.1f | %.1f | %.2f | %.0f |\n", baud, limit, median,
                samples.front(), samples.back(), median / limit, overhead_us);
  }
  return 0;
}
