// A Line over a Linux tty (USB RS485 adapter, on-board UART, or a pseudo-terminal in tests):
// moves the bytes of one transaction at a time and keeps the bus timing (the quiet gap
// between master packets, the reply timeout, retries). It knows no protocol: the request's
// ReplyFramer says when a reply is complete.
//
// The port is a TtyPort (serial/tty_port.h): opened with the bus's termios settings, kernel
// RS485 and the low-latency flag, and, when it fails (EIO from an unplugged adapter, a vanished
// device file), closed and reopened in the background with exponential back-off; meanwhile
// transact() returns LineError::closed at once. Nothing here throws or ends the process.
//
// Timing: a packet ends when its write completes plus its wire time at the baud rate (10 bits
// a byte, 11 with parity or two stop bits). The next packet starts no earlier than that end + the request's
// settle + the bus gap; the reply timeout also runs from that end. Input received before a
// packet is discarded (TCIFLUSH), for line noise.
//
// Late replies: an attempt that timed out may still be answered (USB adapters add latency each
// way; a slow sensor). Before anything else is sent (a retry, or the next transaction), the
// line waits, within transact(), for the late-reply window to close: the bus's own reply wait
// (`timeout`) plus `late_guard` after the end of the request (max_timeout_ms with the
// defaults), or the attempt's own deadline if that is later (a reply wait adapted past it). A
// request's own guard (a scan's probe) counts from its deadline instead. What arrives meanwhile
// is discarded and reported as late bursts (last_timing(), stats().late_replies), so it is
// never taken as the reply to a later request; a burst ends once the line has been quiet for
// 20 ms (serial/late_window.h), and one running when the window closes keeps the line until
// it ends. The window is the line's time a failing attempt costs, the same however late the
// sensor was: docs/operations.md, "One failing sensor never takes its line". On a protocol
// whose replies name their sender (replies_name_sender) two cases end sooner: an attempt that
// received a garbled reply waits only for it to end (its device did answer), and a request
// that asks for it (release_when_silent) is given up 20 ms after its deadline when nothing at
// all was heard, the window then reported in LineTiming::late_window_end. After a transaction
// whose retry succeeded the line also keeps quiet for the guard, since the first attempt's
// answer may still be on its way. A line that never falls quiet (a babbling device) is given
// up on one guard time after the window, so the bus cannot be held forever.
//
// The machine's own lateness: a tty's received bytes reach the line through a kernel worker
// that a loaded machine can leave waiting (serial/delivery_probe.h). So a reply wait that ends
// without a whole reply first waits until this machine has handed on everything the port had
// received by then (a probe byte through the same path), then looks once more: a reply whose
// bytes were in the kernel before the deadline is on time, however late they were handed on
// or the event loop woke. If the machine was behind (the probe took kMachineBehind or more),
// the reply wait starts again from then (a pseudo-terminal's request waits for the same
// worker), counted in stats().machine_held and LineTiming::machine_held. A machine still
// holding the bytes kMaxMachineHold after the deadline gives the attempt up as
// LineError::overloaded: nothing is learnt of the device, and it is not retried.
//
// Echo (an adapter that hears its own transmission): the echo is read back and compared with
// what was sent. A mismatch means another transmitter collided with ours; that attempt fails
// like a time-out (retried, counted in stats().timeouts and echo_mismatches()), because the
// port itself is fine and LineError::io would wrongly make drivers think it was unplugged.
// A request without a framer is only written; its echo goes with the next request's flush.
//
// 9-bit framing: address bytes go out with mark parity, then tcdrain (which blocks the event
// loop for the few byte-times the address takes), then space parity for the data bytes.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "driver/captured_frame.h"
#include "driver/framing.h"
#include "driver/line.h"
#include "serial/frame_tap.h"
#include "serial/line_port.h"
#include "serial/low_latency.h"
#include "serial/port_deadline.h"
#include "serial/termios_settings.h"
#include "serial/tty_port.h"

namespace tiltgate {

// A line's framing and timing: what the gateway makes of a [[bus]] and its protocol's
// descriptor (gateway/serial_options.h).
struct SerialLineOptions {
  std::string name;  // for log lines, e.g. "line1"
  // A tty path, e.g. /dev/ttyUSB0 (a symlink is followed at every open), or a serial device
  // server's URL (device_server/port_url.h), whose port the maker below opens.
  std::string port;
  std::uint32_t baud = 125000;
  std::chrono::milliseconds timeout{50};  // reply timeout per attempt
  int retries = 2;                        // extra attempts after a time-out
  // How long past the bus's reply wait the line stays quiet after a time-out (late replies
  // above): the late-reply window closes timeout + late_guard after the request.
  std::chrono::milliseconds late_guard{450};
  std::chrono::microseconds gap{1000};    // quiet time between master packets
  bool rs485_kernel = false;              // TIOCSRS485; a port without it logs a warning
  bool echo = false;                      // the adapter hears its own transmission
  std::chrono::milliseconds reopen_min{500};
  std::chrono::milliseconds reopen_max{10000};
  Framing framing = Framing::eight_none_one;
  // Take an advisory lock (flock) on the tty while it is open, so that a commissioning command
  // opening it directly is told it is in use instead of talking over the gateway.
  bool exclusive = false;
  // Set the driver's low-latency flag at each open (serial/low_latency.h); false leaves it alone.
  bool low_latency = true;
  // The protocol's replies name the device that sends them (driver/family.h), so a garbled
  // reply means that device answered: after it the line keeps one reply wait of quiet, not
  // the whole late-reply window, and a request may ask to be given up early when silent.
  bool replies_name_sender = false;
  // Where sysfs is mounted, to read a USB adapter's latency_timer for the log (tests: a fake).
  std::string sysfs_root = "/sys";
};

class SerialLine final : public Line {
 public:
  // Test hook: called after each write, with the termios read back from the port right then,
  // so a test can see the parity an address byte went out with.
  using WriteObserver = std::function<void(std::span<const std::uint8_t> written,
                                           Parity applied, const TtySettings& in_force)>;
  // Test hook: asked at a reply deadline instead of the port's delivery probe, as
  // DeliveryProbe::measure() is (how long the machine took to hand on what it had received).
  using DeliveryCheck = std::function<boost::asio::awaitable<
      std::optional<std::chrono::microseconds>>(std::chrono::milliseconds limit)>;

  // Makes the port the line runs on; `on_reopened` is to be called after each successful open
  // but the first.
  using PortMaker =
      std::function<std::unique_ptr<LinePort>(std::function<void()> on_reopened)>;

  // On the tty options.port names.
  SerialLine(boost::asio::any_io_executor executor, SerialLineOptions options);
  // On the port `make_port` makes (device_server/serial_line_maker.h: a device server's).
  SerialLine(boost::asio::any_io_executor executor, SerialLineOptions options,
             const PortMaker& make_port);
  // Calls stop(). Destroy the line only when no transact() is suspended on it.
  ~SerialLine() override;
  SerialLine(const SerialLine&) = delete;
  SerialLine& operator=(const SerialLine&) = delete;

  // Opens the port. A port that cannot be opened yet is not an error: it is logged and retried
  // in the background with back-off. Returns whether the port is open now.
  bool start();
  // Opens the line again after stop() (a redundant pair's gateway takes its lines back); false
  // where its port cannot come back (a device server's).
  bool restart() { return port_->resume() && (start(), true); }
  // Closes the port and cancels everything: a suspended transact() returns cancelled, and so
  // does every later one. A stopped line does not start again.
  void stop();

  boost::asio::awaitable<Expected<Done, LineError>> transact(LineRequest request) override;

  std::uint64_t generation() const override { return port_->generation(); }
  bool is_open() const override { return port_->is_open(); }
  // The port's first open is under way (LinePort::opening): transact() waits for it.
  bool opening() const { return port_->opening(); }
  // Why the port is not open, where it knows (LinePort::failure: a device server's).
  std::optional<PortFailure> connection_failure() const { return port_->failure(); }
  int retries() const override { return options_.retries; }
  const std::string& name() const override { return options_.name; }
  const LineStats& stats() const override { return stats_; }
  const LineTiming& last_timing() const override { return timing_; }
  // A request's wire time, the reply wait, and the late-reply window after a time-out.
  std::chrono::milliseconds longest_attempt(std::chrono::milliseconds timeout,
                                            std::size_t request_bytes) const override;
  std::uint64_t echo_mismatches() const { return echo_mismatches_; }
  const SerialLineOptions& options() const { return options_; }

  // The settings in force on the open port (nullopt while closed).
  std::optional<TtySettings> termios_in_force() { return port_->settings_in_force(); }
  // What setting the low-latency flag gave at the latest open (nothing: not tried yet, or
  // low_latency is off).
  const std::optional<LowLatencyResult>& low_latency() const { return port_->low_latency(); }
  void observe_writes(WriteObserver observer) { write_observer_ = std::move(observer); }
  // Asked before each request goes out, with what the line received since the last exchange
  // (read where the port can, not dropped unread): false keeps the request back, nothing sent
  // (LineError::closed). A redundant pair's active gateway stops at once when it hears another
  // master (redundancy/master_guard.h).
  using SendCheck = std::function<bool(std::span<const std::uint8_t> received)>;
  void check_before_sending(SendCheck check) { send_check_ = std::move(check); }
  // Every frame the line carries from now on goes to `recorder` (capture/black_box.h), which
  // must outlive the line; null stops it. Stray bytes flushed before a request are counted
  // (LineStats::stray_bytes), not recorded: they are dropped unread.
  void record_frames_to(FrameRecorder* recorder) { tap_.record_to(recorder); }
  std::chrono::seconds frames_kept() const override { return tap_.kept(); }
  void check_delivery_with(DeliveryCheck check) { delivery_check_ = std::move(check); }

 private:
  // withheld: the send check (check_before_sending()) kept it back.
  enum class Attempt { replied, timed_out, overloaded, failed, cancelled, withheld };

  // A probe through the kernel taking this long means the machine was behind.
  static constexpr std::chrono::milliseconds kMachineBehind{2};
  // How long past a reply deadline the machine may hold the line's bytes.
  static constexpr std::chrono::seconds kMaxMachineHold{2};
  // An overloaded machine is logged at most this often.
  static constexpr std::chrono::seconds kOverloadLogInterval{60};
  using Clock = std::chrono::steady_clock;

  // A read, write or termios call that failed: counted, and the port given up for reopening.
  Attempt port_failure(const std::string& why);

  boost::asio::awaitable<Attempt> attempt(const LineRequest& request,
                                          std::chrono::milliseconds timeout);
  // When the late-reply window of an attempt of `request` that just timed out closes.
  Clock::time_point late_window_end(const LineRequest& request,
                                    std::chrono::milliseconds timeout) const;
  // How long the line must be quiet for a late burst to have ended (serial/late_window.h).
  std::chrono::milliseconds burst_quiet() const;
  // What the port's UART counted wrong since `before` (taken before an attempt) into the
  // transaction's timing; nothing where the port cannot count.
  void note_uart_counts(const UartCounts& before);
  // Discards what arrives until `window_end` and any late burst then running has ended, each
  // burst counted as a late reply to the request that ended at `request_end`; with
  // `look_end`, stops there if nothing has arrived by then (the window is then reported in
  // LineTiming::late_window_end). Returns the attempt's outcome if the port failed or the line
  // stopped meanwhile.
  boost::asio::awaitable<std::optional<Attempt>> discard_late_replies(
      Clock::time_point window_end, Clock::time_point request_end,
      std::optional<Clock::time_point> look_end = std::nullopt);
  // What the port adds to a reply wait (LinePort::network_allowance), whole milliseconds.
  std::chrono::milliseconds network_allowance() const {
    return std::chrono::ceil<std::chrono::milliseconds>(port_->network_allowance());
  }
  // Waits out the quiet time after the previous packet; false once stopped.
  boost::asio::awaitable<bool> keep_quiet();
  // Send steps return the attempt's outcome if it ends there, nothing if it goes on.
  boost::asio::awaitable<std::optional<Attempt>> send(const LineRequest& request);
  boost::asio::awaitable<std::optional<Attempt>> write_segment(std::span<const std::uint8_t> bytes,
                                                               Parity parity);
  boost::asio::awaitable<Attempt> receive(const LineRequest& request, Clock::time_point deadline);
  // At a reply wait's deadline: waits until the machine has handed on what the port received
  // so far; moves `deadline` a whole `wait` past now when it was behind. Returns the attempt's
  // end when the machine still held the bytes at `hold_limit`, or the line stopped.
  boost::asio::awaitable<std::optional<Attempt>> wait_for_machine(Clock::time_point& deadline,
                                                                  Clock::time_point hold_limit,
                                                                  Clock::duration wait);
  // One read that gives up at `deadline`: how many bytes came, or timed_out when none came in
  // time, or the outcome of a failed port or a stopped line.
  boost::asio::awaitable<Expected<std::size_t, Attempt>> read_before(std::span<std::uint8_t> buffer,
                                                                      Clock::time_point deadline);

  SerialLineOptions options_;
  std::chrono::milliseconds request_late_guard_{0};  // this transaction's (LineRequest::late_guard)
  std::unique_ptr<LinePort> port_;
  boost::asio::steady_timer quiet_timer_;
  PortDeadline deadline_;  // after port_: it cancels reads and writes on port_'s descriptor
  Clock::time_point packet_end_{};   // when the last byte written leaves the UART
  Clock::time_point last_byte_at_{}; // when the last byte was received
  bool heard_ = false;  // the current attempt received bytes (its reply, or garbage)
  Clock::time_point quiet_until_{};  // earliest start of the next master packet
  std::uint64_t echo_mismatches_ = 0;
  LineStats stats_;
  LineTiming timing_;
  WriteObserver write_observer_;
  SendCheck send_check_;
  std::vector<std::uint8_t> received_before_;  // what the send check is shown
  DeliveryCheck delivery_check_;
  std::optional<Clock::time_point> overload_logged_at_;
  // The frames it carries, for its recorder (record_frames_to), and the current attempt's
  // bytes, which the trace log shows too.
  FrameTap tap_;
  // --log-level trace (serial/frame_trace.h): set per transaction.
  bool tracing_ = false;
};

}  // namespace tiltgate
