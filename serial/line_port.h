// What a SerialLine moves its bytes through: a local tty (serial/tty_port.h) or a connection to
// a serial device server (device_server/network_port.h). The line keeps the timing and the
// transactions; a port only opens, reopens after a loss, and carries bytes.
//
// Reads and writes go through stream(), one descriptor either way (a tty, or a TCP socket), so
// the line's deadline cancels them the same way. A port whose wire has its own byte stuffing
// (Telnet doubles 0xFF) turns the bytes on their way through outgoing() and incoming().
#pragma once

#include <boost/asio/posix/stream_descriptor.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "driver/expected.h"
#include "serial/low_latency.h"
#include "serial/termios_settings.h"

namespace tiltgate {

class DeliveryProbe;

// Why a port that is not open is not (a device server's connection that failed or was lost).
struct PortFailure {
  // How the server turned the connection away, if it did: it refused it, or closed or reset it
  // on its own (a serial device server does so to a second client of a port another one holds).
  enum class Kind { other, refused, closed };
  std::string why;  // as the system or the server said it
  Kind kind = Kind::other;
};

class LinePort {
 public:
  virtual ~LinePort() = default;

  // Opens the port, or starts to: one that cannot be opened yet is logged and retried with
  // back-off. Returns whether the port is open now.
  virtual bool open() = 0;
  // Closes the port for good: a pending read or write completes with operation_aborted, and
  // nothing reopens it.
  virtual void stop() = 0;
  // Closes a port that failed under the line and reopens it with back-off; `why` is logged.
  virtual void lose(const std::string& why) = 0;

  virtual bool is_open() const = 0;
  // The first open is under way and may still succeed soon (a connection being made): an
  // exchange waits for it rather than finding the line closed. False on a tty.
  virtual bool opening() const { return false; }
  // Why the latest connect failed, or the connection was lost, while the port is not open;
  // none while it is open, before any failure, and on a tty (which logs its own reasons).
  virtual std::optional<PortFailure> failure() const { return std::nullopt; }
  virtual bool stopped() const = 0;
  // Undoes stop(): the port may be opened again (a redundant pair's gateway that gave up its
  // lines takes them back). False where a stopped port cannot come back (a network port).
  virtual bool resume() { return false; }
  // Successful opens so far.
  virtual std::uint64_t generation() const = 0;
  // For the reads and writes; closed (and every operation on it failing) while the port is.
  virtual boost::asio::posix::stream_descriptor& stream() = 0;

  // Writes what the port takes now, without waiting: how many of `bytes` (0 when its buffer is
  // full), or why it failed.
  virtual Expected<std::size_t, std::string> write_now(std::span<const std::uint8_t> bytes) = 0;
  // What the port's UART counted wrong since it opened (overruns, framing and parity errors);
  // none where the port cannot count them (a pseudo-terminal, a network port, many USB
  // adapters).
  virtual std::optional<UartCounts> uart_counts() { return std::nullopt; }
  // Drops what was received and not read yet (line noise, a late answer) before a request:
  // how many bytes it dropped, where the port can tell (0 where it cannot).
  virtual Expected<std::size_t, std::string> discard_input() = 0;
  // The same, but what was received is appended to `into` where the port can read it without
  // waiting (a tty); elsewhere it is dropped as discard_input() does. For a redundant pair's
  // guard, which must see another master's requests (redundancy/master_guard.h).
  virtual Expected<std::size_t, std::string> take_input(std::vector<std::uint8_t>& into) {
    (void)into;
    return discard_input();
  }
  // The bytes to write for `bytes` (the same span on a tty; a Telnet port's escaped copy,
  // valid until the next call).
  virtual std::span<const std::uint8_t> outgoing(std::span<const std::uint8_t> bytes) {
    return bytes;
  }
  // Turns what a read put in `chunk` into the line's bytes, in place; returns how many of them
  // there are (a Telnet port takes out its commands).
  virtual std::size_t incoming(std::span<std::uint8_t> chunk) { return chunk.size(); }

  // A 9-bit bus's per-byte parity: switch it now (address bytes go with mark), and wait for
  // what was written to leave first. A port that cannot switch says why.
  virtual Expected<Done, std::string> switch_parity(Parity parity) = 0;
  virtual Expected<Done, std::string> wait_until_sent() = 0;

  // The settings in force on the open tty; nothing while closed or on a network port.
  virtual std::optional<TtySettings> settings_in_force() { return std::nullopt; }
  // What setting the low-latency flag gave at the latest open (nothing: not tried, or not a tty).
  virtual const std::optional<LowLatencyResult>& low_latency() const {
    static const std::optional<LowLatencyResult> none;
    return none;
  }
  // The time a reply spends on the network on top of the far line's own: the connection's
  // measured round trip with its variation (zero on a tty). The line adds it to every reply
  // wait and late-reply window.
  virtual std::chrono::microseconds network_allowance() const { return {}; }
  // What tells whether this machine has handed on what the port received (a tty's bytes pass a
  // kernel worker: serial/delivery_probe.h); none where the path has no such hold (a network
  // port, whose round trip the line allows for instead).
  virtual DeliveryProbe* delivery_probe() { return nullptr; }
  // The connection's smoothed round trip alone, which the line takes off a measured reply time
  // so that a sensor's adapted reply wait stays the sensor's own (zero on a tty).
  virtual std::chrono::microseconds round_trip() const { return {}; }
};

}  // namespace tiltgate
