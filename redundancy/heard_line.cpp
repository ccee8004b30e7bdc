#include "redundancy/heard_line.h"

#include <algorithm>

#include "redundancy/heard_exchanges.h"

namespace tiltgate {

namespace asio = boost::asio;

HeardLine::HeardLine(std::shared_ptr<HeardExchanges> heard) : heard_(std::move(heard)) {}

const std::string& HeardLine::name() const { return heard_->bus_line().name(); }

std::chrono::seconds HeardLine::frames_kept() const { return heard_->bus_line().frames_kept(); }

asio::awaitable<Expected<Done, LineError>> HeardLine::transact(LineRequest request) {
  using Clock = HeardExchanges::Clock;
  timing_ = LineTiming{};
  std::uint64_t& taken = taken_[request.bytes];
  const HeardExchanges::Heard* heard = heard_->find(request.bytes);
  if (heard == nullptr || heard->seq <= taken) {
    // A request the master repeats comes again within its interval, give or take the master's
    // own retries and turns; one heard once only (just after listening began, or an identity
    // read) is given a second to come again.
    if (heard == nullptr) co_return Unexpected(LineError::expired);
    const auto wait =
        heard->times < 2 ? Clock::duration{kFirstRepeatWait}
                         : std::min<Clock::duration>(
                               2 * heard->interval + std::chrono::milliseconds{100}, kLongestWait);
    const std::uint64_t after = taken;
    if (!co_await heard_->wait_for(request.bytes, after, Clock::now() + wait))
      co_return Unexpected(heard_->waits_stopped() ? LineError::cancelled : LineError::expired);
    heard = heard_->find(request.bytes);
    if (heard == nullptr) co_return Unexpected(LineError::expired);
  }
  taken_[request.bytes] = heard->seq;
  took_ = true;
  ++stats_.attempts;
  if (request.framer == nullptr) co_return Done{};
  if (!heard->reply) {
    ++stats_.timeouts;
    co_return Unexpected(LineError::timeout);
  }
  const std::vector<std::uint8_t>& reply = *heard->reply;
  timing_.bytes_in = std::uint32_t(reply.size());
  stats_.bytes_in += reply.size();
  request.framer->reset();
  if (!heard->reply_intact || !request.framer->feed(reply)) {
    timing_.garbled = true;
    ++stats_.timeouts;
    co_return Unexpected(LineError::timeout);
  }
  timing_.reply_delay = std::chrono::duration_cast<std::chrono::milliseconds>(
      std::max(heard->reply_end - heard->request_end, Clock::duration{0}));
  timing_.reply_at = heard->reply_end;
  co_return Done{};
}

}  // namespace tiltgate
