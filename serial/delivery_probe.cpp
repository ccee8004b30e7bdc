#include "serial/delivery_probe.h"

#include <fcntl.h>
#include <unistd.h>

#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <spdlog/spdlog.h>

namespace tiltgate {

namespace asio = boost::asio;
using Clock = std::chrono::steady_clock;

DeliveryProbe::DeliveryProbe(asio::any_io_executor executor) : executor_(std::move(executor)) {}

DeliveryProbe::~DeliveryProbe() { stop(); }

void DeliveryProbe::stop() {
  stopped_ = true;
  if (arrivals_) {
    boost::system::error_code ignored;
    arrivals_->reader.close(ignored);  // the waiting read ends with operation_aborted
    arrivals_->arrived.cancel();       // and so does a measure() in progress
    arrivals_.reset();
  }
  pty_.reset();
}

bool DeliveryProbe::open() {
  if (arrivals_) return true;
  if (unavailable_ || stopped_) return false;
  auto pty = PseudoTerminal::open();
  std::string why = pty ? "" : pty.error();
  if (pty && ::fcntl(pty->slave_fd(), F_SETFL, ::fcntl(pty->slave_fd(), F_GETFL) | O_NONBLOCK) == 0) {
    auto arrivals = std::make_shared<Arrivals>(executor_);
    const int master = pty->release_master();
    boost::system::error_code ec;
    // Registered with epoll now, while nothing is in flight (registering polls the tty).
    arrivals->reader.assign(master, ec);
    if (!ec) {
      arrivals_ = std::move(arrivals);
      pty_.emplace(std::move(*pty));
      read_next(arrivals_);
      return true;
    }
    ::close(master);
    why = ec.message();
  } else if (pty) {
    why = "cannot make it non-blocking";
  }
  unavailable_ = true;
  spdlog::warn("no pseudo-terminal for the delivery probe ({}): a reply wait ends at its "
               "deadline even when this machine held the reply back",
               why);
  return false;
}

void DeliveryProbe::read_next(const std::shared_ptr<Arrivals>& arrivals) {
  arrivals->reader.async_read_some(
      asio::buffer(arrivals->buffer),
      [arrivals](const boost::system::error_code& ec, std::size_t count) {
        if (ec) return;  // closed: the probe stopped
        arrivals->received += count;
        if (arrivals->awaited != 0 && arrivals->received >= arrivals->awaited)
          arrivals->arrived.cancel();
        read_next(arrivals);
      });
}

asio::awaitable<std::optional<std::chrono::microseconds>> DeliveryProbe::measure(
    std::chrono::milliseconds limit) {
  if (!open()) co_return std::chrono::microseconds{0};
  const std::shared_ptr<Arrivals> arrivals = arrivals_;
  const Clock::time_point start = Clock::now();
  const std::uint8_t byte = 0x55;
  if (::write(pty_->slave_fd(), &byte, 1) != 1) co_return std::chrono::microseconds{0};
  arrivals->awaited = ++sent_;
  arrivals->arrived.expires_at(start + limit);
  boost::system::error_code ec;  // cancelled: the byte is in (or the probe stopped)
  co_await arrivals->arrived.async_wait(asio::redirect_error(asio::use_awaitable, ec));
  const bool through = arrivals->received >= arrivals->awaited;
  arrivals->awaited = 0;
  if (!through) co_return std::nullopt;
  co_return std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start);
}

}  // namespace tiltgate
