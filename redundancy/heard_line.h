// One sensor poller's line on a standby gateway: transact() sends nothing; it answers a
// request with what the same request got when the active master sent it (HeardExchanges), the
// reply fed to the driver's framer as if it had come to us, dated when it was heard. Each
// hearing is taken once. A request whose hearing was taken already waits for the next (at most
// twice its interval, a second while it was heard only once); one never heard is "not sent"
// (LineError::expired), which changes nothing of the sensor. No retries: the master's
// own are heard as hearings of their own.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "driver/line.h"

namespace tiltgate {

class HeardExchanges;

class HeardLine final : public Line {
 public:
  explicit HeardLine(std::shared_ptr<HeardExchanges> heard);

  boost::asio::awaitable<Expected<Done, LineError>> transact(LineRequest request) override;
  // One generation: what the standby learnt of a sensor stays true while it listens.
  std::uint64_t generation() const override { return 1; }
  bool is_open() const override { return true; }
  int retries() const override { return 0; }
  const std::string& name() const override;
  const LineStats& stats() const override { return stats_; }
  const LineTiming& last_timing() const override { return timing_; }
  std::chrono::seconds frames_kept() const override;
  bool listens_only() const override { return true; }

  // Whether a transaction took a hearing since the last call (HeardExchanges::pace()).
  bool take_news() { return std::exchange(took_, false); }

  // The longest a repeated request is waited for, whatever its interval.
  static constexpr std::chrono::seconds kLongestWait{30};
  // How long a request heard once is waited for to come again.
  static constexpr std::chrono::seconds kFirstRepeatWait{1};

 private:
  std::shared_ptr<HeardExchanges> heard_;
  std::map<std::vector<std::uint8_t>, std::uint64_t> taken_;  // each request's hearing taken last
  LineStats stats_;
  LineTiming timing_;
  bool took_ = false;
};

}  // namespace tiltgate
