// What a standby gateway heard the active master ask on one line, and what each request got:
// the latest hearing of every distinct request (its exact bytes), numbered, so that each
// sensor's poller on the standby (redundancy/heard_line.h) takes each answer once, as soon as
// it is heard. Fed by the line's passive decoder (capture/passive_decoder.h) through
// LineListener; everything runs on the gateway's event loop.
//
// A request heard twice or more is one the master repeats (a measurement): a poller asking it
// again waits for its next hearing. One heard once (an identity read at the master's start) is
// taken when it is there and not waited for.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "capture/passive_decoder.h"
#include "line_scheduling/heard_source.h"

namespace tiltgate {

class HeardExchanges final : public HeardTrafficSink,
                             public HeardSource,
                             public std::enable_shared_from_this<HeardExchanges> {
 public:
  using Clock = std::chrono::steady_clock;

  struct Heard {
    std::uint64_t seq = 0;    // 1, 2, ... over every request of the line
    std::uint32_t times = 0;  // hearings of this request since listening began
    std::chrono::nanoseconds interval{0};  // between its last two hearings
    Clock::time_point request_end{};        // its last byte
    std::optional<std::vector<std::uint8_t>> reply;  // none: no reply heard
    bool reply_intact = false;
    Clock::time_point reply_end{};
  };

  // `bus_line`: the bus's own line (its name, its black box), outliving this.
  // `character_time`: one character on the wire, to date a frame's last byte from its first.
  HeardExchanges(boost::asio::any_io_executor executor, const Line& bus_line,
                 std::chrono::nanoseconds character_time);

  void on_frame(const HeardFrame& frame) override;
  void on_exchange(const HeardExchange& exchange) override;

  // The latest hearing of `request`, or null.
  const Heard* find(std::span<const std::uint8_t> request) const;
  // Waits until `request` is heard with a number above `after`, until `until`, or until
  // stop_waits(): whether it was.
  boost::asio::awaitable<bool> wait_for(std::span<const std::uint8_t> request, std::uint64_t after,
                                        Clock::time_point until);
  // Waits until a request not heard before is heard, until `until` or stop_waits().
  boost::asio::awaitable<void> wait_for_news(Clock::time_point until);
  // Every wait ends now, and a wait begun until resume_waits() ends at once: the gateway takes
  // the line, or stops.
  void stop_waits();
  void resume_waits();
  bool waits_stopped() const { return stopped_; }

  // When the last intact request was heard (its first byte); none before the first.
  std::optional<Clock::time_point> last_request() const { return last_request_; }
  std::uint64_t requests_heard() const { return requests_heard_; }
  const Line& bus_line() const { return bus_line_; }

  std::unique_ptr<Line> line_for_poller() override;
  boost::asio::awaitable<void> pace(Line& line) override;

  // Distinct requests kept at most; past it the one heard longest ago is forgotten.
  static constexpr std::size_t kMaxRequests = 4096;

 private:
  struct Waiter {
    std::span<const std::uint8_t> request;  // empty: any request not heard before
    boost::asio::steady_timer* timer;
  };
  // Ends the waits `request` satisfies (news: it was new).
  void wake(std::span<const std::uint8_t> request, bool news);
  Clock::time_point steady_time(std::chrono::system_clock::time_point wall) const;
  boost::asio::awaitable<void> sleep(boost::asio::steady_timer& timer, Waiter waiter);

  boost::asio::any_io_executor executor_;
  const Line& bus_line_;
  std::chrono::nanoseconds character_time_;
  std::map<std::vector<std::uint8_t>, Heard> heard_;
  std::uint64_t next_seq_ = 1;
  std::list<Waiter> waiters_;
  std::optional<Clock::time_point> last_request_;
  std::uint64_t requests_heard_ = 0;
  bool stopped_ = false;
};

}  // namespace tiltgate
