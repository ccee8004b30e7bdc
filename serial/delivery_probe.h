// Whether the kernel hands a tty's received bytes to their reader promptly right now. Every
// byte a tty receives (a UART's, a USB adapter's, a pseudo-terminal's) waits in the tty layer's
// flip buffer until a kernel worker thread moves it on (flush_to_ldisc, on the unbound
// workqueue), and on a loaded machine the scheduler has left that worker waiting for up to 2 s
// while the reply it held was long in (docs/performance.md, "A flood and the line"). A reply
// wait that ends meanwhile would blame the sensor for the machine.
//
// The probe sends one byte through a pseudo-terminal of its own, the same path, and times it.
// The worker runs its queue in order, so once the byte is through, whatever any tty received
// before it was handed on too. A read is always waiting on the probe's tty, asked for while
// nothing was in flight, so the byte is taken when epoll says it is in: a read, a poll or an
// epoll_ctl of a tty with bytes still in its flip buffer waits inside the kernel for that very
// worker (n_tty_read, n_tty_poll: tty_buffer_flush_work), which would stop the whole event loop.
// (Asio's async_wait re-arms the descriptor with epoll_ctl each time, so it is not used here.)
//
// One probe per line; on the line's event loop. A machine without pseudo-terminals gives no
// probe: measure() then says the path is clear, and the line times out as it always did.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/posix/stream_descriptor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <array>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>

#include "serial/pseudo_terminal.h"

namespace tiltgate {

class DeliveryProbe {
 public:
  explicit DeliveryProbe(boost::asio::any_io_executor executor);
  ~DeliveryProbe();
  DeliveryProbe(const DeliveryProbe&) = delete;
  DeliveryProbe& operator=(const DeliveryProbe&) = delete;

  // How long a byte sent now took to come through, or nothing when it was not through within
  // `limit` (the kernel's worker still waits). Zero when there is no probe.
  boost::asio::awaitable<std::optional<std::chrono::microseconds>> measure(
      std::chrono::milliseconds limit);
  // Ends a measure() in progress (it returns nothing) and any later one at once: the line stops.
  void stop();

 private:
  // What the waiting read shares with measure(); its handler may run after the probe is gone.
  struct Arrivals {
    boost::asio::posix::stream_descriptor reader;  // the master side: the bytes arrive here
    boost::asio::steady_timer arrived;  // measure() waits on it; cancelled when its byte is in
    std::array<std::uint8_t, 64> buffer{};
    std::uint64_t received = 0;  // bytes read so far
    std::uint64_t awaited = 0;   // the count measure() waits for; 0: nobody waits
    explicit Arrivals(boost::asio::any_io_executor executor) : reader(executor), arrived(executor) {}
  };

  // Opens the pseudo-terminal the first time; false when there is none to be had.
  bool open();
  // Keeps a read waiting on the probe's tty.
  static void read_next(const std::shared_ptr<Arrivals>& arrivals);

  boost::asio::any_io_executor executor_;
  std::optional<PseudoTerminal> pty_;  // holds the slave side, which the byte is written to
  std::shared_ptr<Arrivals> arrivals_;
  std::uint64_t sent_ = 0;      // bytes written so far
  bool unavailable_ = false;    // the pseudo-terminal could not be had: logged once
  bool stopped_ = false;
};

}  // namespace tiltgate
