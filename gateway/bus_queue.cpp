#include "gateway/bus_queue.h"

#include <algorithm>
#include <boost/asio/redirect_error.hpp>
#include <boost/asio/use_awaitable.hpp>

namespace tiltgate {

namespace asio = boost::asio;

std::shared_ptr<BusJob> BusQueue::push(BusWork work) {
  jobs_.push_back(std::make_shared<BusJob>(executor_, std::move(work)));
  return jobs_.back();
}

asio::awaitable<bool> BusQueue::wait(std::shared_ptr<BusJob> job,
                                     SteadyClock::time_point deadline) {
  job->done.expires_at(deadline);
  while (!job->answer) {
    boost::system::error_code ec;
    co_await job->done.async_wait(asio::redirect_error(asio::use_awaitable, ec));
    if (job->answer || ec == asio::error::operation_aborted) continue;
    // The deadline passed.
    if (std::erase(jobs_, job) == 1) {
      job->answer = expiry(job->work);
      co_return false;
    }
    job->done.expires_at(SteadyClock::time_point::max());  // on the wire: waited for
  }
  co_return true;
}

template <class Work>
std::deque<std::shared_ptr<BusJob>>::iterator BusQueue::first() {
  return std::find_if(jobs_.begin(), jobs_.end(), [](const std::shared_ptr<BusJob>& job) {
    return std::holds_alternative<Work>(job->work);
  });
}

std::shared_ptr<BusJob> BusQueue::take(std::deque<std::shared_ptr<BusJob>>::iterator at) {
  std::shared_ptr<BusJob> job = std::move(*at);
  jobs_.erase(at);
  return job;
}

std::shared_ptr<BusJob> BusQueue::take(bool poll_due) {
  if (auto write = first<SensorWrite>(); write != jobs_.end()) return take(write);
  if (poll_due && turn_taken_) return nullptr;
  const auto command = first<CommandTransaction>();
  const auto forward = first<ForwardRequest>();
  if (command == jobs_.end() && forward == jobs_.end()) return nullptr;
  turn_taken_ = true;
  command_last_ = command != jobs_.end() && (forward == jobs_.end() || !command_last_);
  return take(command_last_ ? command : forward);
}

std::size_t BusQueue::queued_forwards() const {
  return std::size_t(std::count_if(jobs_.begin(), jobs_.end(), [](const auto& job) {
    return std::holds_alternative<ForwardRequest>(job->work);
  }));
}

void BusQueue::refuse_turns() {
  std::erase_if(jobs_, [](const std::shared_ptr<BusJob>& job) {
    if (std::holds_alternative<SensorWrite>(job->work)) return false;
    job->answer_with(refusal(job->work));
    return true;
  });
}

void BusQueue::refuse_all() {
  for (const std::shared_ptr<BusJob>& job : jobs_) job->answer_with(refusal(job->work));
  jobs_.clear();
}

}  // namespace tiltgate
