// The device side of a simulated serial bus: serves a pseudo-terminal that the gateway (or a
// test) opens as if it were a USB-RS485 adapter. It knows no protocol: bytes read from the
// master side go to a callback, and whatever the simulated devices answer goes back out, each
// send at its own time, after its delay (and, when pacing, its transmission time at a baud
// rate), as devices on a line answer: a late reply holds up no one else's, and two sends that
// would be on the line at the same time collide, both arriving with every byte broken.
// Each sensor family's simulator is a protocol layer on top of it. At trace level it logs the
// bytes it reads and each send it writes, in hex, named by its pty ("sim /dev/pts/4 <- ...").
//
// A second master (a warm-standby pair's other gateway) gets a pseudo-terminal of its own on
// the same line: every master hears what the others write and every device's send, and bytes
// that would be on the line together collide (serial/shared_wire.h has the rule). The line is
// then always timed, at the pace baud or else at the baud the first master's tty is set to.
//
// Threading: the server runs on the caller's io_context, which must outlive it. Call its
// methods from the thread running that io_context (or through post()), or while it is not
// running. The callbacks run on that thread and may call send(), send_after() and unplug().
#pragma once

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/expected.h"
#include "serial/shared_wire.h"

namespace tiltgate {

struct PtyBusServerOptions {
  // A stable path re-pointed (atomically) at the current slave on every (re)open and removed
  // on unplug, since a new pseudo-terminal gets a new /dev/pts number. Empty: no link.
  std::string link_path;
  // Pace sends as a real line at this baud would: each also waits bytes * bits_per_byte / baud
  // seconds. Off by default so tests run fast (a line with a second master is always timed).
  std::optional<std::uint32_t> pace_baud;
  // Bits on the wire per byte: 10 for 8N1; 11 for 8E1 and 9-bit framing.
  unsigned bits_per_byte = 10;
  // Hear only what is sent while the tty is set to this baud rate: a device set to one rate
  // makes nothing of bytes sent at another, so a master at the wrong rate gets no reply. The
  // rate is read from the pseudo-terminal, which shares its settings with the slave side.
  std::optional<std::uint32_t> listen_baud = std::nullopt;
  // A second master on the line, served on a pseudo-terminal of its own: the path of its link
  // (as link_path; empty: none). Without it the line has one master.
  std::optional<std::string> second_master_link = std::nullopt;
};

struct PtyBusCounters {
  std::uint64_t bytes_received = 0;
  std::uint64_t bytes_unheard = 0;  // received at another rate than listen_baud, dropped
  std::uint64_t bytes_sent = 0;
  std::uint64_t sends_completed = 0;  // send() / send_after() calls whose bytes were all written
  // Sends and masters' transmissions that would have been on the line at once, sent broken.
  std::uint64_t collisions = 0;
  std::uint64_t master_collisions = 0;  // of those, the ones a master's bytes were in
};

// One master's side of the line, as that master sees it.
struct MasterCounters {
  std::uint64_t bytes_sent = 0;      // what it wrote onto the line
  std::uint64_t bytes_received = 0;  // what reached it: the devices' sends, the others' bytes
};

class PtyBusServer {
 public:
  // Bytes as read from the master side: any split of what the other side wrote.
  using Receiver = std::function<void(std::span<const std::uint8_t>)>;
  // One send's bytes have all been written (to the first master that took them).
  using SendCompleted = std::function<void()>;
  // Masters' bytes broken in a collision crossed the line: the devices heard only noise, and
  // their framing starts afresh.
  using NoiseHeard = std::function<void()>;

  PtyBusServer(boost::asio::io_context& io, PtyBusServerOptions options, Receiver on_received,
               SendCompleted on_sent = {}, NoiseHeard on_noise = {});
  ~PtyBusServer();
  PtyBusServer(const PtyBusServer&) = delete;
  PtyBusServer& operator=(const PtyBusServer&) = delete;

  // Opens every master's pseudo-terminal (and link) and starts serving them; open ones are
  // unplugged first.
  Expected<Done, std::string> start();
  // Closes a master's pseudo-terminal (the first's by default) and removes its link: that
  // gateway's next read or write on the slave fails as on an unplugged adapter. Once no master
  // is left, the sends not yet written are dropped.
  void unplug(std::size_t master = 0);
  // A new pseudo-terminal for a master (a new slave path; the link follows it).
  Expected<Done, std::string> replug(std::size_t master = 0);
  // Stops serving every master for good; the destructor does it too.
  void stop();

  // Writes `bytes` once `delay` (plus the transmission time, on a timed line) has passed since
  // this call, or, on a timed line, since the bytes received so far would have finished
  // arriving at its baud rate; earlier due sends first. One that would overlap another on the
  // line (a late reply and the next device's) is sent broken, and so is the other. It goes to
  // every master plugged when it is due. While none is plugged the bytes are dropped, as a
  // powered device's answer is when no adapter listens.
  void send_after(std::chrono::steady_clock::duration delay, std::vector<std::uint8_t> bytes);
  void send(std::vector<std::uint8_t> bytes) { send_after({}, std::move(bytes)); }

  // 1, or 2 with a second master.
  std::size_t masters() const;
  bool plugged(std::size_t master = 0) const;
  // A master's current slave path; empty while unplugged.
  const std::string& slave_path(std::size_t master = 0) const;
  const std::string& link_path(std::size_t master = 0) const;
  // The line's: the bytes of every master, each device's send once.
  PtyBusCounters counters() const;
  const MasterCounters& master_counters(std::size_t master) const;

 private:
  struct Port;
  struct Master;
  struct SendTimer;

  // Whether bytes received now are at listen_baud (always, without one).
  bool hears(int master_fd) const;
  void read_more(const std::shared_ptr<Port>& port);
  void received(const std::shared_ptr<Port>& port, std::size_t count);
  void deliver_crossed(std::size_t from);
  void arm_send_timer();
  void write_due_sends();
  void queue_write(std::size_t master, std::vector<std::uint8_t> bytes,
                   std::shared_ptr<bool> send_done);
  void write_next(const std::shared_ptr<Port>& port);
  void wrote(const std::shared_ptr<Port>& port, std::size_t written);
  // How long `bytes` take on the wire: at the pace baud; with a second master, else at the
  // baud the first plugged master's tty is set to; else no time.
  std::chrono::steady_clock::duration transmission_time(std::size_t bytes) const;

  boost::asio::io_context& io_;
  PtyBusServerOptions options_;
  Receiver on_received_;
  SendCompleted on_sent_;
  NoiseHeard on_noise_;
  std::vector<Master> masters_;
  SharedWire wire_;
  std::shared_ptr<SendTimer> send_timer_;  // shared with its handler, which outlives the server
  PtyBusCounters counters_;  // but its collisions, which the wire counts
  // When the bytes received so far would have finished arriving on a real line.
  std::chrono::steady_clock::time_point receiving_until_{};
};

}  // namespace tiltgate
