// The seam between drivers and serial buses. A driver speaks a protocol as a sequence of
// transactions; a Line moves the bytes of one transaction at a time and knows nothing of the
// protocol beyond "has a whole reply arrived yet", which the driver's ReplyFramer answers.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/expected.h"

namespace tiltgate {

enum class LineError {
  timeout,  // no complete reply within the reply timeout (after every retry)
  io,       // the port failed (unplugged adapter, I/O error); the line reopens by itself
  closed,   // the port is not open right now (reopening with back-off)
  cancelled, // shutdown
  // Not sent: the one it was sent for must have its answer before the attempt could end (a
  // write's write_timeout_ms, line_scheduling/line_claimant.h). The sensor was not asked.
  expired,
  // The machine held what the line received past the reply wait and a long grace after it (the
  // kernel's tty worker did not run: serial/delivery_probe.h): nothing was learnt of the device,
  // whose reply may well have come.
  overloaded
};

const char* to_string(LineError e);

// A framer's account of one attempt's bytes, for `--log-level trace` (serial/frame_trace.h).
// The family words the verdicts with its own checksum's name.
struct FramerReport {
  // The accepted reply as it was on the wire, checksum included; empty before feed() returned
  // true.
  std::vector<std::uint8_t> reply;
  // The checksum's verdict on the reply, e.g. "CRC ok".
  std::string reply_verdict;
  // What became of the bytes that were not the reply when a frame among them failed its
  // checks, e.g. "bad CRC"; empty when they were only skipped (noise, another device's frame).
  std::string rejected_verdict;
};

// Decides when the bytes received so far hold a whole reply. Pure: fed by the Line, owned by
// the driver, which reads the decoded reply out of it afterwards.
class ReplyFramer {
 public:
  virtual ~ReplyFramer() = default;
  // Forget everything; called before each attempt of a transaction.
  virtual void reset() = 0;
  // Consume received bytes. Returns true once a complete, valid reply is held; bytes after it
  // are ignored. Bytes that cannot be part of a valid reply are dropped by the framer itself.
  virtual bool feed(std::span<const std::uint8_t> bytes) = 0;
  // What the framer made of the bytes fed since reset(), for the trace log. The Line asks only
  // when trace logging is on. The default knows no checksum: the Line then shows what it read.
  virtual FramerReport report() const { return {}; }

  // A framer that must ask someone else whether the reply is whole (the gateway's relay to a
  // commissioning command, control/control_relay.h) says so: the Line then awaits
  // feed_async() instead of calling feed(), so that its event loop never waits for the answer.
  // Every other framer is asked with feed(): no coroutine frame per chunk on the polls' path.
  virtual bool asks_asynchronously() const { return false; }
  virtual boost::asio::awaitable<bool> feed_async(std::span<const std::uint8_t> bytes) {
    co_return feed(bytes);
  }
};

struct LineRequest {
  std::vector<std::uint8_t> bytes;
  // Leading bytes of `bytes` that are address bytes (sent with the 9th bit set on a 9-bit
  // bus, i.e. mark parity). Zero on byte-oriented protocols.
  std::size_t address_bytes = 0;
  // Null for a request that gets no reply (the Line then only writes).
  ReplyFramer* framer = nullptr;
  // Zero means the bus's configured reply timeout. Drivers pass the sensor's own, which adapts
  // upward when it answers late (driver/adaptive_reply_timeout.h).
  std::chrono::milliseconds timeout{0};
  // Extra attempts after a time-out. -1 means the bus's configured retries. A driver sets 0
  // for commands that must not run twice (set address).
  int retries = -1;
  // Quiet time the Line keeps after this transaction before the next one (e.g. a sensor that
  // needs 50 ms after it was given a new address).
  std::chrono::milliseconds settle{0};
  // After a time-out, how long the line must stay quiet before anything else is sent (see
  // LineTiming). None: the bus's own guard. A scan's probes of empty addresses give a short
  // one: nothing is late there, and the bus's guard would cost every probe half a second.
  std::optional<std::chrono::milliseconds> late_guard{};
  // After a time-out with nothing heard at all, the line may be given up after a short look
  // (20 ms past the deadline) instead of the whole late-reply window; a byte in the look holds
  // the whole window. LineTiming::late_window_end then says when the window
  // would have closed: nothing may be sent to this device before (line_scheduling/line_claimant.h).
  bool release_when_silent = false;
};

struct LineStats {
  std::uint64_t attempts = 0;   // requests written, retries included
  std::uint64_t timeouts = 0;   // attempts that timed out
  std::uint64_t late_replies = 0;  // bursts of bytes after a time-out, discarded (LineTiming)
  std::uint64_t io_errors = 0;  // failed reads/writes
  std::uint64_t reopens = 0;    // successful (re)opens after the first
  // Reply waits made longer because this machine had not handed on what the line received by
  // their deadline (serial/delivery_probe.h), and attempts given up as overloaded.
  std::uint64_t machine_held = 0;
  std::uint64_t overloaded = 0;
  // Bytes written to the line and read from it, and of those read, the bytes found waiting
  // before a request (line noise, a device babbling between frames), dropped unread.
  std::uint64_t bytes_out = 0;
  std::uint64_t bytes_in = 0;
  std::uint64_t stray_bytes = 0;
};

// What the Line saw of the timing of the last transact(), for drivers that adapt their reply
// time-out. A Line knows no protocol: it reports bursts of bytes, not replies.
//
// A late reply is a burst of bytes that arrives after an attempt timed out. The Line does not
// send again until the line has been quiet for its guard time, so a late burst belongs to the
// transaction whose request provoked it: it is discarded and reported here, never fed to a
// later request's framer.
struct LineTiming {
  // From the end of the request to the completion of the reply that answered it; none when no
  // reply came in time.
  std::optional<std::chrono::milliseconds> reply_delay;
  // Bursts of bytes discarded after a time-out (serial/serial_line.h: a burst ends when the
  // line has been quiet for 20 ms): one per late reply.
  std::uint32_t late_replies = 0;
  // The longest time from the end of the timed-out request to the last byte of its late burst:
  // how long the sensor really took. None without late replies.
  std::optional<std::chrono::milliseconds> late_delay;
  // The last attempt timed out with bytes received that made no reply (a broken checksum, a
  // collision): the device answered, garbled.
  bool garbled = false;
  // The last attempt timed out silent and the line was given up after a short look
  // (LineRequest::release_when_silent): until then the device's late reply may still come.
  std::optional<std::chrono::steady_clock::time_point> late_window_end;
  // How long this machine held what the line received past reply deadlines (the reply waits
  // were made that much longer): the machine's lateness, none of the device's.
  std::chrono::milliseconds machine_held{0};
  // Bytes written and read in the transaction, late replies included, and what the port's UART
  // counted wrong meanwhile (0 where it cannot count): characters lost to overruns, characters
  // with a framing or parity error.
  std::uint32_t bytes_out = 0;
  std::uint32_t bytes_in = 0;
  std::uint32_t overruns = 0;
  std::uint32_t uart_errors = 0;
  // When the reply's last byte came, where the line knows it better than the moment
  // transact() returns (a standby's line: the reply was heard earlier, redundancy/heard_line.h).
  // A reading is dated with it.
  std::optional<std::chrono::steady_clock::time_point> reply_at;
};

// When a reply taken on `timing`'s transaction arrived: its own time where the line knows it,
// else now.
inline std::chrono::steady_clock::time_point reply_time(const LineTiming& timing) {
  return timing.reply_at.value_or(std::chrono::steady_clock::now());
}

class Line {
 public:
  virtual ~Line() = default;
  // Run one request/reply exchange. Only one runs at a time; the caller (the bus) serialises.
  virtual boost::asio::awaitable<Expected<Done, LineError>> transact(LineRequest request) = 0;
  // Increments on every successful (re)open, so a driver can tell that the device may have
  // been replaced or power-cycled and re-read its identity.
  virtual std::uint64_t generation() const = 0;
  virtual bool is_open() const = 0;
  // The extra attempts after a time-out that a request leaving them to the bus (retries = -1)
  // gets: the bus's retries.
  virtual int retries() const = 0;
  virtual const std::string& name() const = 0;
  virtual const LineStats& stats() const = 0;
  // The timing of the last transact(), valid once it has returned and until the next one.
  virtual const LineTiming& last_timing() const = 0;
  // The longest one attempt of a request of `request_bytes` bytes with reply time-out
  // `timeout` can hold the line: its wire time, the reply wait, and the late-reply guard kept
  // after a time-out. This default knows no wire time and no guard.
  // How many seconds of its frames the line's black box keeps (capture/black_box.h); zero
  // when none does (a command's line).
  virtual std::chrono::seconds frames_kept() const { return std::chrono::seconds{0}; }
  // A standby's line (redundancy/heard_line.h): it sends nothing and answers each request with
  // what the active master's same request got, when that is heard. A driver then takes no
  // answer to its identity request as "not heard yet", not as a silent sensor.
  virtual bool listens_only() const { return false; }
  virtual std::chrono::milliseconds longest_attempt(std::chrono::milliseconds timeout,
                                                    std::size_t request_bytes) const {
    (void)request_bytes;
    return timeout;
  }
};

}  // namespace tiltgate
