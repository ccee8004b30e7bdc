// One serial bus: the only owner of its Line. Polls each sensor at its poll period, and backs
// off from sensors that do not answer so they cannot starve the others. Between polls it
// carries out the jobs its callers queue and wait for (gateway/bus_job.h): writes of its
// sensors ahead of polls, requests forwarded to devices passed through ([[bus]] pass_through)
// and the transactions of commissioning commands (the control socket) taking turns with the
// polls, in the order gateway/bus_queue.h gives them. Everything runs on the event loop
// thread; nothing here blocks.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "driver/forwarded_exchange.h"
#include "driver/line.h"
#include "driver/sensor_driver.h"
#include "gateway/bus_job.h"
#include "gateway/bus_queue.h"
#include "gateway/gateway_sensor.h"
#include "gateway/poll_schedule.h"
#include "gateway/sensor_write.h"

namespace tiltgate {

struct BusSchedulerStats {
  std::uint64_t polls = 0;
  std::uint64_t writes = 0;
  std::uint64_t writes_expired = 0;  // still queued at their deadline
  // Requests forwarded to devices passed through.
  std::uint64_t forwarded = 0;         // answered by the device (exception replies included)
  std::uint64_t forward_timeouts = 0;  // no reply: time-out, port closed or failed
  std::uint64_t forwards_expired = 0;  // still queued at their deadline
  std::uint64_t forwards_busy = 0;     // refused at once: the queue was full
  std::uint64_t forwards_unframed = 0; // the protocol had no frame for the PDU
  // Transactions of commissioning commands through the control socket.
  std::uint64_t command_exchanges = 0;  // carried out (whatever the line made of them)
  std::uint64_t command_exchanges_expired = 0;  // still queued at their deadline
  // Time spent in polls, writes, forwarded requests and commands' transactions, waiting for
  // replies and time-outs included: the share of the wire's time this bus uses.
  std::chrono::nanoseconds busy{0};
};

class BusScheduler {
 public:
  BusScheduler(boost::asio::any_io_executor executor, Line& line, std::string name);

  // Polls `sensor` from now on. This overload does not own it: the caller keeps it alive.
  void add(GatewaySensor& sensor);
  // The same, and keeps the sensor alive while it is polled or its poll is on the wire (a
  // reload may drop every other reference meanwhile).
  void add(std::shared_ptr<GatewaySensor> sensor);
  // Polls `sensor` no more (a reload removed or replaced it). Its writes already queued are
  // still carried out and answered: they hold the sensor.
  void remove(const GatewaySensor& sensor);
  // Winds the bus down for a reload that removed or changed it: no more polls; forwarded
  // requests and commands still queued are answered as at stop(); the writes already queued
  // (and any queued meanwhile) are carried out, and then run() returns, as after stop().
  void retire();
  bool retiring() const { return retiring_; }
  // Runs until stop(). Spawn it once.
  boost::asio::awaitable<void> run();
  void stop();

  // Checks `write` (a refusal is answered at once, before anything is queued), queues it
  // ahead of every poll and waits for it: all its settings, one after another. A write still
  // queued when `deadline` passes is dropped and answered busy; one already on the wire is
  // always waited for (its transactions are bounded by the bus time-outs).
  boost::asio::awaitable<WriteResult> write(SensorWrite write, SteadyClock::time_point deadline);

  // Refuses (bad_value: Modbus 0x03) a write that would move `sensor` to the address another
  // sensor on this bus has now: both would answer it, the bus would collide, and moving one
  // back would move both. SensorWrite asks before the write is queued and again as each of
  // its settings starts.
  WriteResult check_address_free(const GatewaySensor& sensor, WriteTarget target,
                                 double value) const;

  // Lets forward() frame requests with the bus protocol's factory (driver/forwarded_exchange.h), with
  // at most `max_queued` of them waiting at once.
  void enable_forwarding(ForwardFactory make, std::size_t max_queued = kMaxQueuedForwards);

  // Queues `pdu` for the device at `slave` and waits for its reply PDU. When forwarded
  // requests and polls are both due they alternate, one exchange each, so neither side can
  // starve the other; writes of the cached sensors stay ahead of both. Each exchange is sent
  // once (retries = 0: the client retries, and a forwarded write must never run twice) with
  // the bus's reply time-out. A request still queued at `deadline` is dropped (expired); one
  // already on the wire is always waited for.
  boost::asio::awaitable<ForwardResult> forward(std::uint8_t slave, std::vector<std::uint8_t> pdu,
                                                SteadyClock::time_point deadline);

  // Runs one transaction of a commissioning command (control/control_server.h) on the line.
  // It takes turns with the polls as forwarded requests do, so every sensor keeps being polled
  // while a command scans or sets. The request is sent as given (its time-out, retries and
  // settle time); its framer must stay alive until this returns. A request still queued at
  // `deadline` is dropped (expired).
  boost::asio::awaitable<CommandExchangeResult> exchange_for_command(
      LineRequest request, SteadyClock::time_point deadline);

  // A commissioning command moved the sensor at bus address `from` to `to`: the sensor polled
  // at `from` follows it. Returns its name, or none when no sensor of this bus was at `from`.
  std::optional<std::string> follow_address(std::uint32_t from, std::uint32_t to);
  // A commissioning command is about to move the sensor at `address`: it is not polled until
  // follow_address() or release(), or until `until` (a poll at its old address while it moves
  // would fail). A poll already on the wire finishes first: the command's next transaction
  // waits for its turn. Returns its name, or none when no sensor of this bus is there.
  std::optional<std::string> hold(std::uint32_t address, SteadyClock::time_point until);
  void release(std::uint32_t address);

  const std::string& name() const { return name_; }
  const BusSchedulerStats& stats() const { return stats_; }
  Line& line() { return line_; }

  // Longest wait between polls of an offline sensor (gateway/poll_schedule.h).
  static constexpr std::chrono::milliseconds max_backoff{5000};
  // Forwarded requests waiting per bus; more are answered busy at once. A Modbus client waits
  // for each reply, so this many means as many clients (or connections) at once.
  static constexpr std::size_t kMaxQueuedForwards = 32;

 private:
  struct Polled {
    std::shared_ptr<GatewaySensor> sensor;
    PollSchedule schedule;
    std::optional<SteadyClock::time_point> held_until{};  // hold(): not polled before then
  };
  Polled* next_due();
  Polled* find_polled(const GatewaySensor* sensor);
  // Polls `sensor` and publishes what it read.
  boost::asio::awaitable<void> poll(std::shared_ptr<GatewaySensor> sensor);
  // Derives mounting, tilt and alarms once per new reading (a new sample_seq).
  static void process_new_reading(GatewaySensor& sensor);
  // Queues `work` (unless the bus stops, or retires and it is no write: then it is answered
  // refusal() at once), waits for its answer and counts it in `expired` when it expired unsent.
  template <class Result>
  boost::asio::awaitable<Result> queue(BusWork work, SteadyClock::time_point deadline,
                                       std::uint64_t& expired);
  // Carries out a job taken from the queue and answers it.
  boost::asio::awaitable<void> carry_out(BusJob& job);
  boost::asio::awaitable<ForwardResult> exchange(const ForwardRequest& forward);
  boost::asio::awaitable<CommandExchangeResult> transact(const CommandTransaction& command);

  Line& line_;
  std::string name_;
  std::vector<Polled> sensors_;
  BusQueue jobs_;
  ForwardFactory make_forward_ = nullptr;
  std::size_t max_queued_forwards_ = kMaxQueuedForwards;
  boost::asio::steady_timer wake_;
  bool stopping_ = false;
  bool retiring_ = false;  // retire(): the queued writes, then stop
  BusSchedulerStats stats_;
};

}  // namespace tiltgate
