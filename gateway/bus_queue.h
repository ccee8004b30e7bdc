// The jobs waiting for one bus (gateway/bus_job.h) and whose turn on the line is next. A write
// of a cached sensor goes ahead of everything. Forwarded requests and commands' transactions
// alternate with each other when both wait, and take turns with due polls, one exchange each:
// a client hammering a passed-through device cannot starve the cached sensors, a busy poll
// schedule cannot starve the client, and every sensor keeps being polled while a command
// scans or sets. A job still queued at its deadline is taken out and answered expiry(), never
// sent; one already taken up is always waited for (the bus's time-outs bound it).
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <deque>
#include <memory>

#include "driver/sensor_state.h"
#include "gateway/bus_job.h"

namespace tiltgate {

class BusQueue {
 public:
  explicit BusQueue(boost::asio::any_io_executor executor) : executor_(std::move(executor)) {}

  std::shared_ptr<BusJob> push(BusWork work);
  // Waits until `job` is answered. False when its deadline passed while it was still queued:
  // it is then taken out and answered expiry().
  boost::asio::awaitable<bool> wait(std::shared_ptr<BusJob> job,
                                    SteadyClock::time_point deadline);

  // Takes out the job whose turn it is: a write, else a forwarded request or command, unless
  // `poll_due` and the last exchange was one of them. None: a due poll's turn, or none waits.
  std::shared_ptr<BusJob> take(bool poll_due);
  // A poll had the line: a forwarded request or command waiting goes next.
  void polled() { turn_taken_ = false; }

  std::size_t queued_forwards() const;
  // Answers the queued forwarded requests and commands refusal() at once (a retiring bus
  // lets its writes finish); refuse_all() the writes too (a stopping bus).
  void refuse_turns();
  void refuse_all();

 private:
  template <class Work>
  std::deque<std::shared_ptr<BusJob>>::iterator first();
  std::shared_ptr<BusJob> take(std::deque<std::shared_ptr<BusJob>>::iterator at);

  boost::asio::any_io_executor executor_;
  std::deque<std::shared_ptr<BusJob>> jobs_;  // in the order they came
  // The last exchange was a forwarded request's or a command's: a due poll goes next.
  bool turn_taken_ = false;
  // Of the turns given to forwarded requests and commands, the last was a command's.
  bool command_last_ = false;
};

}  // namespace tiltgate
