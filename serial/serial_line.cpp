// SerialLine's exchanges: a request written, its reply framed, time-outs and retries, and the
// quiet guard that keeps a late reply from answering the next request. Opening and reopening
// the port is TtyPort's (serial/tty_port.cpp).
#include "serial/serial_line.h"

#include <unistd.h>

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <utility>

#include "serial/delivery_probe.h"
#include "serial/frame_trace.h"
#include "serial/late_window.h"

namespace tiltgate {

namespace asio = boost::asio;
using boost::system::error_code;

namespace {

// A driver takes a short packet into its buffer at once; a write not accepted within a second
// (beyond the packet's own wire time) means the port is wedged.
constexpr std::chrono::seconds kStalledWrite{1};


// The port's share of the line's options.
TtyPortOptions port_options_of(const SerialLineOptions& line) {
  return {.name = line.name,
          .path = line.port,
          .baud = line.baud,
          .parity = idle_parity(line.framing),
          .stop_bits = stop_bits_of(line.framing),
          .rs485_kernel = line.rs485_kernel,
          .exclusive = line.exclusive,
          .low_latency = line.low_latency,
          .sysfs_root = line.sysfs_root,
          .reopen_min = line.reopen_min,
          .reopen_max = line.reopen_max};
}

// Rounded up, and never negative (a pty delivers a reply before the request's estimated wire
// time has passed).
std::chrono::milliseconds whole_ms(std::chrono::steady_clock::duration d) {
  return std::max(std::chrono::ceil<std::chrono::milliseconds>(d), std::chrono::milliseconds{0});
}

}  // namespace

SerialLine::SerialLine(asio::any_io_executor executor, SerialLineOptions options)
    : SerialLine(executor, std::move(options), [this, executor](std::function<void()> on_reopened) {
        // options_ is set by now: it is the first member.
        return std::make_unique<TtyPort>(executor, port_options_of(options_),
                                         std::move(on_reopened));
      }) {}

SerialLine::SerialLine(asio::any_io_executor executor, SerialLineOptions options,
                       const PortMaker& make_port)
    : options_(std::move(options)),
      port_(make_port([this] { ++stats_.reopens; })),
      quiet_timer_(executor),
      deadline_(executor, port_->stream()),
      tap_(options_.baud, options_.framing) {}

SerialLine::~SerialLine() { stop(); }

bool SerialLine::start() { return port_->open(); }

void SerialLine::stop() {
  port_->stop();
  quiet_timer_.cancel();
  deadline_.cancel();
}

SerialLine::Attempt SerialLine::port_failure(const std::string& why) {
  if (port_->stopped()) return Attempt::cancelled;  // stop() closed the port under the operation
  ++stats_.io_errors;
  port_->lose(why);
  return Attempt::failed;
}

asio::awaitable<Expected<Done, LineError>> SerialLine::transact(LineRequest request) {
  const int retries = request.retries < 0 ? options_.retries : request.retries;
  const auto timeout = request.timeout.count() > 0 ? request.timeout : options_.timeout;
  timing_ = LineTiming{};
  request_late_guard_ = request.late_guard.value_or(options_.late_guard);
  // Decided once per transaction: with trace off, nothing below is kept or formatted.
  tracing_ = spdlog::should_log(spdlog::level::trace);
  std::optional<Clock::time_point> timed_out_request_end;
  while (port_->opening()) {  // bounded by the port's own connect time-out
    quiet_timer_.expires_after(std::chrono::milliseconds{5});
    error_code ec;
    co_await quiet_timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    if (port_->stopped()) co_return Unexpected(LineError::cancelled);
  }
  for (int attempts_left = retries + 1;; --attempts_left) {
    if (port_->stopped()) co_return Unexpected(LineError::cancelled);
    if (!port_->is_open()) co_return Unexpected(LineError::closed);
    const std::optional<UartCounts> uart_before = port_->uart_counts();
    Attempt outcome = co_await attempt(request, timeout);
    if (uart_before) note_uart_counts(*uart_before);
    if (outcome == Attempt::overloaded) {
      tap_.reply_lost(request.framer, "no reply: held by this machine");
      // Its reply may still come: kept off the next request like a late one.
      const auto guarded =
          co_await discard_late_replies(late_window_end(request, timeout), packet_end_);
      co_return Unexpected(guarded == Attempt::cancelled ? LineError::cancelled
                                                         : LineError::overloaded);
    }
    if (outcome == Attempt::timed_out) {
      ++stats_.timeouts;
      spdlog::debug("{}: no reply within {} ms", options_.name, timeout.count());
      if (tracing_ && request.framer) {
        spdlog::trace("{} {}", options_.name,
                      traced_timeout(tap_.heard_bytes(), request.framer->report(), timeout));
      }
      tap_.reply_lost(request.framer, "no reply");
      timed_out_request_end = packet_end_;
      timing_.garbled = heard_;
      std::optional<Clock::time_point> look_end;
      if (request.release_when_silent && options_.replies_name_sender && !heard_ &&
          !request.late_guard) {
        look_end = std::max(Clock::now(), packet_end_ + timeout + network_allowance()) +
                   burst_quiet();
      }
      const auto guarded =
          co_await discard_late_replies(late_window_end(request, timeout), packet_end_, look_end);
      if (guarded) outcome = *guarded;
    } else if (outcome == Attempt::replied && timed_out_request_end) {
      // An earlier attempt's answer may still be on its way: let it land here, not in the
      // next transaction.
      const auto guarded = co_await discard_late_replies(Clock::now() + request_late_guard_,
                                                         *timed_out_request_end);
      if (guarded) outcome = *guarded;
    }
    switch (outcome) {
      case Attempt::replied: co_return Done{};
      case Attempt::failed: co_return Unexpected(LineError::io);
      case Attempt::cancelled: co_return Unexpected(LineError::cancelled);
      case Attempt::withheld: co_return Unexpected(LineError::closed);
      case Attempt::overloaded: co_return Unexpected(LineError::overloaded);
      case Attempt::timed_out:
        if (attempts_left <= 1) co_return Unexpected(LineError::timeout);
        break;
    }
  }
}

void SerialLine::note_uart_counts(const UartCounts& before) {
  const std::optional<UartCounts> after = port_->uart_counts();
  if (!after) return;
  const auto grown = [](std::uint64_t now, std::uint64_t then) {
    return std::uint32_t(now > then ? now - then : 0);  // a reopened port counts from 0
  };
  timing_.overruns += grown(after->overruns, before.overruns);
  timing_.uart_errors += grown(after->framing_errors, before.framing_errors);
}

SerialLine::Clock::time_point SerialLine::late_window_end(const LineRequest& request,
                                                          std::chrono::milliseconds timeout) const {
  // From the deadline: an echo mismatch ends the attempt before it.
  const Clock::time_point deadline =
      std::max(Clock::now(), packet_end_ + timeout + network_allowance());
  // A request's own guard (a scan's probe) counts from its deadline, as it always did.
  if (request.late_guard) return deadline + request_late_guard_;
  // Its device answered, garbled (a broken checksum, a collision), and says so itself: no late
  // reply is to come, only the garbled one's tail (discard_late_replies waits for it to end).
  if (heard_ && options_.replies_name_sender) return deadline;
  // Anchored at the request: with the defaults, max_timeout_ms after it, whatever the sensor's
  // adapted reply wait (a reply later than max_timeout_ms is as good as none).
  return std::max(packet_end_ + options_.timeout + network_allowance() + request_late_guard_,
                  deadline);
}

std::chrono::milliseconds SerialLine::burst_quiet() const {
  return LateWindow{options_.timeout, request_late_guard_}.burst_quiet();
}

std::chrono::milliseconds SerialLine::longest_attempt(std::chrono::milliseconds timeout,
                                                      std::size_t request_bytes) const {
  const auto wire = wire_time(request_bytes, options_.baud, idle_parity(options_.framing),
                              stop_bits_of(options_.framing));
  const LateWindow window{options_.timeout, options_.late_guard};
  return std::chrono::ceil<std::chrono::milliseconds>(wire + port_->network_allowance()) +
         window.held_after(timeout);
}

asio::awaitable<std::optional<SerialLine::Attempt>> SerialLine::discard_late_replies(
    Clock::time_point window_end, Clock::time_point request_end,
    std::optional<Clock::time_point> look_end) {
  const auto burst_quiet = this->burst_quiet();
  // A line that never falls quiet (a babbling device) is given up on one guard time later.
  const Clock::time_point give_up = window_end + request_late_guard_;
  Clock::time_point quiet_until =
      look_end ? *look_end : std::max(window_end, last_byte_at_ + burst_quiet);
  bool in_burst = false;
  std::vector<std::uint8_t> discarded;  // kept for the trace log only
  std::array<std::uint8_t, 256> buffer{};
  for (;;) {
    const Clock::time_point until = std::min(quiet_until, give_up);
    if (Clock::now() >= until) break;
    const Clock::time_point previous_byte = last_byte_at_;
    const Expected<std::size_t, Attempt> received = co_await read_before(buffer, until);
    if (!received && received.error() == Attempt::timed_out) break;  // quiet
    if (!received) co_return received.error();
    if (*received == 0) continue;
    if (tracing_) discarded.insert(discarded.end(), buffer.begin(), buffer.begin() + *received);
    quiet_until = std::max(window_end, last_byte_at_ + burst_quiet);
    const bool starts_burst = !in_burst || last_byte_at_ - previous_byte > burst_quiet;
    if (starts_burst) {
      in_burst = true;
      ++timing_.late_replies;
      ++stats_.late_replies;
    }
    tap_.late(std::span<const std::uint8_t>(buffer.data(), *received), starts_burst);
    timing_.late_delay = std::max(timing_.late_delay.value_or(std::chrono::milliseconds{0}),
                                  whole_ms(last_byte_at_ - request_end - port_->round_trip()));
  }
  tap_.late_done();
  if (quiet_until > give_up) {
    spdlog::debug("{}: still receiving {} ms after the request, sending anyway", options_.name,
                  whole_ms(give_up - request_end).count());
  }
  // Nothing came in the look: the line goes on, the device's window stays its own.
  if (look_end && !in_burst) timing_.late_window_end = window_end;
  if (in_burst) {
    spdlog::debug("{}: discarded a reply {} ms after the request, past its time-out",
                  options_.name, timing_.late_delay->count());
    if (tracing_) {
      spdlog::trace("{} {}", options_.name, traced_late(discarded, *timing_.late_delay));
    }
  }
  // The guard itself is the quiet time before the next packet; the bus gap still applies.
  quiet_until_ = std::max(quiet_until_, Clock::now() + options_.gap);
  co_return std::nullopt;
}

asio::awaitable<SerialLine::Attempt> SerialLine::attempt(const LineRequest& request,
                                                         std::chrono::milliseconds timeout) {
  const bool quiet = co_await keep_quiet();
  if (!quiet) co_return Attempt::cancelled;
  if (request.framer) request.framer->reset();
  heard_ = false;
  // Bytes that arrived since the last reply (a late answer, line noise) would be taken for
  // the start of this reply.
  received_before_.clear();
  auto flushed = send_check_ ? port_->take_input(received_before_) : port_->discard_input();
  if (!flushed) co_return port_failure(flushed.error());
  stats_.stray_bytes += *flushed;
  stats_.bytes_in += *flushed;
  if (send_check_ && !send_check_(received_before_)) co_return Attempt::withheld;
  ++stats_.attempts;
  const auto sent_at = std::chrono::system_clock::now();
  const std::optional<Attempt> send_failure = co_await send(request);
  if (send_failure) co_return *send_failure;
  const std::size_t address_bytes =
      options_.framing == Framing::nine_bit ? std::min(request.address_bytes, std::size_t{255})
                                            : 0;
  if (tracing_)
    spdlog::trace("{} {}", options_.name, traced_request(request.bytes, address_bytes));
  tap_.request_sent(sent_at, request.bytes, std::uint8_t(address_bytes), request.framer != nullptr,
                    tracing_);
  quiet_until_ = packet_end_ + request.settle + options_.gap;
  if (!request.framer) co_return Attempt::replied;  // nothing to wait for: written is done
  co_return co_await receive(request, packet_end_ + timeout + network_allowance());
}

asio::awaitable<bool> SerialLine::keep_quiet() {
  if (Clock::now() < quiet_until_) {
    quiet_timer_.expires_at(quiet_until_);
    error_code ec;
    co_await quiet_timer_.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  }
  co_return !port_->stopped();
}

asio::awaitable<std::optional<SerialLine::Attempt>> SerialLine::send(const LineRequest& request) {
  std::span<const std::uint8_t> bytes(request.bytes);
  const std::size_t address_bytes =
      options_.framing == Framing::nine_bit ? std::min(request.address_bytes, bytes.size()) : 0;
  if (address_bytes > 0) {
    auto marked = port_->switch_parity(Parity::mark);
    if (!marked) co_return port_failure(marked.error());
    const std::optional<Attempt> address_failure =
        co_await write_segment(bytes.first(address_bytes), Parity::mark);
    if (address_failure) co_return address_failure;
    // The parity must not change while the address is still in the UART. tcdrain blocks the
    // event loop, but only for the few byte-times the address takes (1.1 ms per byte at 9600).
    auto drained = port_->wait_until_sent();
    if (!drained) co_return port_failure(drained.error());
    auto spaced = port_->switch_parity(Parity::space);
    if (!spaced) co_return port_failure(spaced.error());
    bytes = bytes.subspan(address_bytes);
    if (bytes.empty()) co_return std::nullopt;
  }
  co_return co_await write_segment(bytes, idle_parity(options_.framing));
}

asio::awaitable<std::optional<SerialLine::Attempt>> SerialLine::write_segment(
    std::span<const std::uint8_t> bytes, Parity parity) {
  const auto wire =
      wire_time(bytes.size(), options_.baud, parity, stop_bits_of(options_.framing));
  // One write for the whole packet: some protocols need a packet's bytes within 125 us of
  // each other (docs/protocols.md, "Packet timing"). The driver nearly always takes a short
  // packet at once: written now, the request leaves as soon as the reply before it was read,
  // with no timer to arm; only what the driver does not take waits, under the stall deadline.
  std::span<const std::uint8_t> pending = port_->outgoing(bytes);
  const Expected<std::size_t, std::string> taken = port_->write_now(pending);
  if (!taken) co_return port_failure(taken.error());
  pending = pending.subspan(*taken);
  if (!pending.empty()) {
    deadline_.start(Clock::now() + wire + kStalledWrite);
    while (!pending.empty()) {
      error_code ec;
      co_await port_->stream().async_wait(asio::posix::descriptor_base::wait_write,
                                          asio::redirect_error(asio::use_awaitable, ec));
      if (ec) {
        const bool stalled = deadline_.finish();
        co_return port_failure(stalled ? std::string("write stalled") : ec.message());
      }
      const Expected<std::size_t, std::string> more = port_->write_now(pending);
      if (!more) {
        deadline_.finish();
        co_return port_failure(more.error());
      }
      pending = pending.subspan(*more);
    }
    deadline_.finish();
  }
  // The driver has the bytes; they are on the wire for `wire` more (its buffer was empty).
  packet_end_ = Clock::now() + wire;
  stats_.bytes_out += bytes.size();
  timing_.bytes_out += std::uint32_t(bytes.size());
  if (write_observer_) {
    auto in_force = port_->settings_in_force();
    if (in_force) write_observer_(bytes, parity, *in_force);
  }
  co_return std::nullopt;
}

asio::awaitable<SerialLine::Attempt> SerialLine::receive(const LineRequest& request,
                                                         Clock::time_point deadline) {
  std::span<const std::uint8_t> echo;
  if (options_.echo) echo = std::span<const std::uint8_t>(request.bytes);
  const Clock::duration wait = deadline - packet_end_;
  const Clock::time_point hold_limit = deadline + kMaxMachineHold;
  std::array<std::uint8_t, 256> buffer{};
  bool last_look = false;  // the deadline passed with the machine caught up: one read more
  for (;;) {
    // Also ends an attempt drowned in bytes that never make a reply.
    if (Clock::now() >= deadline) {
      if (last_look) co_return Attempt::timed_out;
      const std::optional<Attempt> held = co_await wait_for_machine(deadline, hold_limit, wait);
      if (held) co_return *held;
      last_look = Clock::now() >= deadline;
    }
    const Expected<std::size_t, Attempt> received =
        co_await read_before(buffer, last_look ? Clock::now() : deadline);
    if (!received && received.error() == Attempt::timed_out) continue;  // the deadline's turn
    if (!received) co_return received.error();
    std::span<const std::uint8_t> chunk(buffer.data(), *received);
    if (!echo.empty()) {
      const std::size_t n = std::min(chunk.size(), echo.size());
      if (!std::equal(chunk.begin(), chunk.begin() + n, echo.begin())) {
        ++echo_mismatches_;
        spdlog::debug("{}: echo differs from what was sent (collision)", options_.name);
        tap_.collision(chunk);
        co_return Attempt::timed_out;
      }
      echo = echo.subspan(n);
      chunk = chunk.subspan(n);
    }
    tap_.heard(chunk);
    if (!chunk.empty()) heard_ = true;
    // A framer that asks someone else is awaited (driver/line.h); the others are not.
    bool whole = false;
    if (!chunk.empty() && request.framer->asks_asynchronously())
      whole = co_await request.framer->feed_async(chunk);
    else if (!chunk.empty())
      whole = request.framer->feed(chunk);
    if (whole) {
      timing_.reply_delay =
          whole_ms(last_byte_at_ - packet_end_ - port_->round_trip() - timing_.machine_held);
      tap_.reply_taken(*request.framer);
      if (tracing_) {
        for (const std::string& line :
             traced_reply(tap_.heard_bytes(), request.framer->report(), *timing_.reply_delay)) {
          spdlog::trace("{} {}", options_.name, line);
        }
      }
      co_return Attempt::replied;
    }
  }
}

asio::awaitable<std::optional<SerialLine::Attempt>> SerialLine::wait_for_machine(
    Clock::time_point& deadline, Clock::time_point hold_limit, Clock::duration wait) {
  DeliveryProbe* probe = port_->delivery_probe();
  if (probe == nullptr && !delivery_check_) co_return std::nullopt;
  const auto limit = std::max(
      std::chrono::ceil<std::chrono::milliseconds>(hold_limit - Clock::now()),
      std::chrono::milliseconds{1});
  const std::optional<std::chrono::microseconds> lag =
      delivery_check_ ? co_await delivery_check_(limit) : co_await probe->measure(limit);
  if (port_->stopped()) co_return Attempt::cancelled;
  if (!lag || *lag >= kMachineBehind) {
    timing_.machine_held += std::chrono::ceil<std::chrono::milliseconds>(lag.value_or(limit));
    ++(lag ? stats_.machine_held : stats_.overloaded);
  }
  if (!lag) {
    const Clock::time_point now = Clock::now();
    if (!overload_logged_at_ || now - *overload_logged_at_ >= kOverloadLogInterval) {
      spdlog::warn("{}: this machine held the line's bytes more than {} s past a reply deadline "
                   "({} time(s) in all): attempts given up as overloaded, no device blamed",
                   options_.name, kMaxMachineHold.count(), stats_.overloaded);
      overload_logged_at_ = now;
    }
    co_return Attempt::overloaded;
  }
  if (*lag >= kMachineBehind) {
    spdlog::debug("{}: the machine was {} us behind at a reply deadline: the reply wait starts "
                  "again",
                  options_.name, lag->count());
    deadline = Clock::now() + wait;
  }
  co_return std::nullopt;
}

asio::awaitable<Expected<std::size_t, SerialLine::Attempt>> SerialLine::read_before(
    std::span<std::uint8_t> buffer, Clock::time_point deadline) {
  error_code ec;
  deadline_.start(deadline);
  const std::size_t received = co_await port_->stream().async_read_some(
      asio::buffer(buffer.data(), buffer.size()), asio::redirect_error(asio::use_awaitable, ec));
  const bool passed = deadline_.finish();
  if (ec) {
    if (!port_->stopped() && passed && ec == asio::error::operation_aborted) {
      co_return Unexpected(Attempt::timed_out);
    }
    co_return Unexpected(port_failure(ec.message()));  // EIO, or end of file after a hang-up
  }
  // A Telnet port takes its commands out: a read of nothing but those is no byte of the line's.
  const std::size_t bytes = port_->incoming(buffer.first(received));
  if (bytes > 0) last_byte_at_ = Clock::now();
  stats_.bytes_in += bytes;
  timing_.bytes_in += std::uint32_t(bytes);
  co_return bytes;
}

}  // namespace tiltgate
