#include "redundancy/heard_exchanges.h"

#include <algorithm>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>

#include "redundancy/heard_line.h"

namespace tiltgate {

namespace asio = boost::asio;

HeardExchanges::HeardExchanges(asio::any_io_executor executor, const Line& bus_line,
                               std::chrono::nanoseconds character_time)
    : executor_(std::move(executor)), bus_line_(bus_line), character_time_(character_time) {}

HeardExchanges::Clock::time_point HeardExchanges::steady_time(
    std::chrono::system_clock::time_point wall) const {
  // The decoder dates frames on the wall clock (a capture's time); the pollers read the steady
  // one. The two are a few microseconds apart here, whatever the wall clock says.
  const auto ago = std::chrono::system_clock::now() - wall;
  return Clock::now() - std::chrono::duration_cast<Clock::duration>(ago);
}

void HeardExchanges::on_frame(const HeardFrame& frame) {
  if (frame.kind != HeardKind::request || !frame.intact) return;
  ++requests_heard_;
  last_request_ = steady_time(frame.frame.time);
}

void HeardExchanges::on_exchange(const HeardExchange& exchange) {
  if (!exchange.request.intact) return;  // nobody would have asked a broken request
  const std::vector<std::uint8_t>& request = exchange.request.frame.bytes;
  auto found = heard_.find(request);
  const bool news = found == heard_.end();
  if (news) {
    if (heard_.size() >= kMaxRequests) {
      const auto oldest = std::min_element(heard_.begin(), heard_.end(), [](const auto& a, const auto& b) {
        return a.second.seq < b.second.seq;
      });
      heard_.erase(oldest);
    }
    found = heard_.emplace(request, Heard{}).first;
  }
  Heard& heard = found->second;
  const Clock::time_point request_end =
      steady_time(exchange.request.frame.time) + character_time_ * request.size();
  if (heard.times > 0) heard.interval = request_end - heard.request_end;
  heard.seq = next_seq_++;
  ++heard.times;
  heard.request_end = request_end;
  heard.reply.reset();
  heard.reply_intact = false;
  if (exchange.reply) {
    const CapturedFrame& reply = exchange.reply->frame;
    heard.reply = reply.bytes;
    heard.reply_intact = exchange.reply->intact;
    heard.reply_end = steady_time(reply.time) + character_time_ * reply.bytes.size();
  }
  wake(request, news);
}

const HeardExchanges::Heard* HeardExchanges::find(std::span<const std::uint8_t> request) const {
  const auto found = heard_.find(std::vector<std::uint8_t>(request.begin(), request.end()));
  return found == heard_.end() ? nullptr : &found->second;
}

void HeardExchanges::wake(std::span<const std::uint8_t> request, bool news) {
  for (const Waiter& waiter : waiters_) {
    const bool wanted = waiter.request.empty()
                            ? news
                            : std::equal(waiter.request.begin(), waiter.request.end(),
                                         request.begin(), request.end());
    if (wanted) waiter.timer->cancel();
  }
}

asio::awaitable<void> HeardExchanges::sleep(asio::steady_timer& timer, Waiter waiter) {
  // Held alive while it waits: a reload or a stop may drop the bus meanwhile.
  const auto keep = shared_from_this();
  const auto registered = waiters_.insert(waiters_.end(), waiter);
  boost::system::error_code ignored;
  co_await timer.async_wait(asio::redirect_error(asio::use_awaitable, ignored));
  waiters_.erase(registered);
}

asio::awaitable<bool> HeardExchanges::wait_for(std::span<const std::uint8_t> request,
                                               std::uint64_t after, Clock::time_point until) {
  asio::steady_timer timer(executor_);
  for (;;) {
    const Heard* heard = find(request);
    if (heard != nullptr && heard->seq > after) co_return true;
    if (stopped_ || Clock::now() >= until) co_return false;
    timer.expires_at(until);
    co_await sleep(timer, Waiter{request, &timer});
  }
}

asio::awaitable<void> HeardExchanges::wait_for_news(Clock::time_point until) {
  if (stopped_) co_return;
  asio::steady_timer timer(executor_);
  timer.expires_at(until);
  co_await sleep(timer, Waiter{{}, &timer});
}

void HeardExchanges::stop_waits() {
  stopped_ = true;
  for (const Waiter& waiter : waiters_) waiter.timer->cancel();
}

void HeardExchanges::resume_waits() { stopped_ = false; }

std::unique_ptr<Line> HeardExchanges::line_for_poller() {
  return std::make_unique<HeardLine>(shared_from_this());
}

asio::awaitable<void> HeardExchanges::pace(Line& line) {
  auto& heard_line = static_cast<HeardLine&>(line);
  if (heard_line.take_news()) co_return;
  co_await wait_for_news(Clock::now() + std::chrono::seconds{1});
}

}  // namespace tiltgate
