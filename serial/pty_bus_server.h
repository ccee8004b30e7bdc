// The device side of a simulated serial bus: serves a pseudo-terminal that the gateway (or a
// test) opens as if it were a USB-RS485 adapter. It knows no protocol: bytes read from the
// master side go to a callback, and whatever the simulated devices answer goes back out, each
// send at its own time, after its delay (and, when pacing, its transmission time at a baud
// rate), as devices on a line answer: a late reply holds up no one else's, and two sends that
// would be on the line at the same time collide, both arriving with every byte broken.
// Each sensor family's simulator is a protocol layer on top of it. At trace level it logs the
// bytes it reads and each send it writes, in hex, named by its pty ("sim /dev/pts/4 <- ...").
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
#include "serial/pseudo_terminal.h"

namespace tiltgate {

struct PtyBusServerOptions {
  // A stable path re-pointed (atomically) at the current slave on every (re)open and removed
  // on unplug, since a new pseudo-terminal gets a new /dev/pts number. Empty: no link.
  std::string link_path;
  // Pace sends as a real line at this baud would: each also waits bytes * bits_per_byte / baud
  // seconds. Off by default so tests run fast.
  std::optional<std::uint32_t> pace_baud;
  // Bits on the wire per byte: 10 for 8N1; 11 for 8E1 and 9-bit framing.
  unsigned bits_per_byte = 10;
  // Hear only what is sent while the tty is set to this baud rate: a device set to one rate
  // makes nothing of bytes sent at another, so a master at the wrong rate gets no reply. The
  // rate is read from the pseudo-terminal, which shares its settings with the slave side.
  std::optional<std::uint32_t> listen_baud = std::nullopt;
};

struct PtyBusCounters {
  std::uint64_t bytes_received = 0;
  std::uint64_t bytes_unheard = 0;  // received at another rate than listen_baud, dropped
  std::uint64_t bytes_sent = 0;
  std::uint64_t sends_completed = 0;  // send() / send_after() calls whose bytes were all written
  std::uint64_t collisions = 0;  // sends that would have been on the line at once, sent broken
};

class PtyBusServer {
 public:
  // Bytes as read from the master side: any split of what the other side wrote.
  using Receiver = std::function<void(std::span<const std::uint8_t>)>;
  // One send's bytes have all been written.
  using SendCompleted = std::function<void()>;

  PtyBusServer(boost::asio::io_context& io, PtyBusServerOptions options, Receiver on_received,
               SendCompleted on_sent = {});
  ~PtyBusServer();
  PtyBusServer(const PtyBusServer&) = delete;
  PtyBusServer& operator=(const PtyBusServer&) = delete;

  // Opens a pseudo-terminal (and the link) and starts serving it; an open one is unplugged first.
  Expected<Done, std::string> start();
  // Closes the pseudo-terminal, drops the sends not yet written and removes the link: the
  // gateway's next read or write on the slave fails as on an unplugged adapter.
  void unplug();
  // A new pseudo-terminal (a new slave path; the link follows it).
  Expected<Done, std::string> replug() { return start(); }
  // Stops serving for good; the destructor does it too.
  void stop() { unplug(); }

  // Writes `bytes` once `delay` (plus the transmission time, when pacing) has passed since this
  // call, or, when pacing, since the bytes received so far would have finished arriving at the
  // baud rate; earlier due sends first. One that would overlap another on the line (a late
  // reply and the next device's) is sent broken, and so is the other. While unplugged the
  // bytes are dropped, as a powered device's answer is when no adapter listens.
  void send_after(std::chrono::steady_clock::duration delay, std::vector<std::uint8_t> bytes);
  void send(std::vector<std::uint8_t> bytes) { send_after({}, std::move(bytes)); }

  bool plugged() const { return port_ != nullptr; }
  // The current slave path; empty while unplugged.
  const std::string& slave_path() const { return slave_path_; }
  const std::string& link_path() const { return options_.link_path; }
  const PtyBusCounters& counters() const { return counters_; }

 private:
  // Whether bytes received now are at listen_baud (always, without one).
  bool hears(int master_fd) const;
  struct Port;

  void read_more(const std::shared_ptr<Port>& port);
  void write_next(const std::shared_ptr<Port>& port);
  std::chrono::steady_clock::duration transmission_time(std::size_t bytes) const;
  Expected<Done, std::string> point_link_at(const std::string& target) const;
  void remove_link() const;

  boost::asio::io_context& io_;
  PtyBusServerOptions options_;
  Receiver on_received_;
  SendCompleted on_sent_;
  std::optional<PseudoTerminal> pty_;
  std::shared_ptr<Port> port_;  // shared with the handlers in flight, which outlive a close
  std::string slave_path_;
  PtyBusCounters counters_;
  // When pacing: when the bytes received so far would have finished arriving on a real line.
  std::chrono::steady_clock::time_point receiving_until_{};
};

}  // namespace tiltgate
