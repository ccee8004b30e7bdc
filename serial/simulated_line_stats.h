// `tiltgate sim FAMILY --stats FILE`: what a simulated line has carried, as one JSON object
// that a test reads while the simulator runs (did the standby gateway transmit? did the pair
// collide?). Rewritten every 100 ms and once more at the end, each time whole: written to
// FILE.tmp and renamed over FILE, so a reader never sees half of one. Not synced to disk: it
// is for the test reading it now, and a sync would hold up the simulated line.
//
// {"masters":[{"link":"/tmp/a","bytes_sent":8,"bytes_received":9},...],
//  "collisions":0,"master_collisions":0,"device_replies":1}
//
// Threading: runs on the caller's io_context, which must outlive it; call it from that thread.
#pragma once

#include <boost/asio/io_context.hpp>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "driver/expected.h"

namespace tiltgate {

struct SimulatedMasterStats {
  std::string link{};  // its link, or its slave path without one (empty while unplugged)
  std::uint64_t bytes_sent = 0;      // what the master wrote onto the line
  std::uint64_t bytes_received = 0;  // what reached it: the devices' sends, the others' bytes
};

struct SimulatedLineStats {
  std::vector<SimulatedMasterStats> masters{};
  // Transmissions that arrived broken because two drove the line at once: devices' sends that
  // overlapped, several devices answering one request, and masters' bytes that collided.
  std::uint64_t collisions = 0;
  std::uint64_t master_collisions = 0;  // of those, the ones a master's bytes were in
  std::uint64_t device_replies = 0;     // the devices' sends written to the masters
};

std::string simulated_line_stats_json(const SimulatedLineStats& stats);

class SimulatedLineStatsFile {
 public:
  using Source = std::function<SimulatedLineStats()>;

  SimulatedLineStatsFile(boost::asio::io_context& io, std::string path, Source source);
  ~SimulatedLineStatsFile();
  SimulatedLineStatsFile(const SimulatedLineStatsFile&) = delete;
  SimulatedLineStatsFile& operator=(const SimulatedLineStatsFile&) = delete;

  // Writes the file now and every 100 ms from now on; the error says why it cannot be written.
  Expected<Done, std::string> start();
  // Writes it a last time (when it was started) and stops; `source` is not called after.
  void stop();

 private:
  struct Rewrites;
  std::shared_ptr<Rewrites> rewrites_;  // shared with the timer's handler
};

}  // namespace tiltgate
