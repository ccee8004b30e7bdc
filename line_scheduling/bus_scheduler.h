// One serial bus: the only owner of its Line, shared (line_scheduling/shared_line.h) among everyone
// who needs it. Each sensor has a poller that polls it at its poll period, backing off from a
// sensor that does not answer; Modbus writes of its sensors, requests forwarded to devices it
// passes through ([[bus]] pass_through) and the transactions of commissioning commands (the
// control socket) wait for the line alongside. Each of them is a LineClaimant
// (line_scheduling/line_claimant.h), and whose turn it is next is decided in one place,
// line_scheduling/line_turns.h: healthy sensors' polls in rounds, and one other turn (a write, a
// forwarded request, a command's transaction, a failing sensor's attempt) between rounds, so a
// failing sensor never takes the line from the others (docs/operations.md, "One failing sensor
// never takes its line"). Everything runs on the event loop thread; nothing here blocks.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "audit/audit_record.h"
#include "driver/forwarded_exchange.h"
#include "driver/line.h"
#include "driver/sensor_driver.h"
#include "line_scheduling/bus_answers.h"
#include "line_scheduling/gateway_sensor.h"
#include "line_scheduling/heard_source.h"
#include "line_scheduling/line_claimant.h"
#include "line_scheduling/poll_schedule.h"
#include "line_scheduling/sensor_write.h"
#include "line_scheduling/shared_line.h"

namespace tiltgate {

class AuditTrail;

struct BusSchedulerStats {
  std::uint64_t polls = 0;
  std::uint64_t writes = 0;
  std::uint64_t writes_expired = 0;  // not started before their deadline
  std::uint64_t writes_offline = 0;  // refused at once: the sensor was known not to answer
  // Requests forwarded to devices passed through.
  std::uint64_t forwarded = 0;         // answered by the device (exception replies included)
  std::uint64_t forward_timeouts = 0;  // no reply: time-out, port closed or failed
  std::uint64_t forwards_expired = 0;  // still queued at their deadline
  std::uint64_t forwards_busy = 0;     // refused at once: the queue was full
  std::uint64_t forwards_unframed = 0; // the protocol had no frame for the PDU
  // Transactions of commissioning commands through the control socket.
  std::uint64_t command_exchanges = 0;  // carried out (whatever the line made of them)
  std::uint64_t command_exchanges_expired = 0;  // still queued at their deadline
  // The bus's loop, or a sensor's poller, failed (an exception) and went on after a pause:
  // logged at error (SharedLine::restart(), poll_failed()).
  std::uint64_t restarts = 0;
  std::uint64_t poll_failures = 0;  // of them, polls
  // Time the line was held, by anyone, waiting for replies and time-outs included: the share
  // of the wire's time this bus uses (SharedLine::busy()).
  std::chrono::nanoseconds busy{0};
};

class BusScheduler {
 public:
  BusScheduler(boost::asio::any_io_executor executor, Line& line, std::string name);
  // Stops (stop()) if it has not.
  ~BusScheduler();
  BusScheduler(const BusScheduler&) = delete;
  BusScheduler& operator=(const BusScheduler&) = delete;

  // Polls `sensor` from now on. This overload does not own it: the caller keeps it alive.
  void add(GatewaySensor& sensor);
  // The same, and keeps the sensor alive while it is polled or its poll is on the wire (a
  // reload may drop every other reference meanwhile).
  void add(std::shared_ptr<GatewaySensor> sensor);
  // Polls `sensor` no more (a reload removed or replaced it). A poll on the wire finishes;
  // its writes already queued are still carried out and answered: they hold the sensor.
  void remove(const GatewaySensor& sensor);
  // Winds the bus down for a reload that removed or changed it: no more polls; forwarded
  // requests and commands still waiting are answered as at stop(); the writes already queued
  // (and any queued meanwhile) are carried out, and then run() returns, as after stop().
  void retire();
  bool retiring() const { return retiring_; }
  // Gives the line out, at each due time too, until stop(). Spawn it once.
  boost::asio::awaitable<void> run();
  // Everyone still waiting is answered as refused; the work holding the line finishes (the
  // line's own stop() cancels it). Its sensors are let go.
  void stop();

  // The gateway is the standby of a redundant pair (docs/operations.md, "Warm standby"): its
  // sensors' pollers read `heard` instead of the line, nothing is sent, and the sensors are
  // published as standby (SensorState::standby). Writes, forwarded requests and commands are
  // refused meanwhile (0x0A: the active gateway's path). Null: the pollers take turns on the
  // line again (the gateway took the lines); the caller ends the waits on the source it gave.
  // A poller waiting for its turn when the bus starts listening sends nothing: it finds the
  // bus listening once its turn comes.
  void listen_to(HeardSource* heard);
  bool listening() const { return heard_ != nullptr; }

  // Whether the system clock is synchronised now (clock/clock_watch.h), asked once per new
  // reading so that each is flagged (DerivedState::clock_synchronised); unset: always. Set
  // before the bus starts; the function must be cheap and safe on the bus's thread.
  void set_clock_check(std::function<bool()> synchronised) {
    clock_synchronised_ = std::move(synchronised);
  }

  // Where the writes it carries out are recorded (line_scheduling/sensor_write.h); none until given
  // (a scheduler tested on its own).
  void set_audit(AuditTrail& trail) { audit_ = &trail; }
  AuditTrail* audit() const { return audit_; }

  // Checks `write` (a refusal is answered at once, before anything is queued) and refuses a
  // write to a sensor known not to answer, or whose poll waits to retry after it did not
  // answer (0x0B at once: nothing is sent), then waits for the line and carries it out: all its settings, one after another. No attempt is sent that
  // could end after `deadline`: a write that cannot start in time is answered busy, one that
  // runs out of time on the way as no response.
  boost::asio::awaitable<WriteResult> write(SensorWrite write, SteadyClock::time_point deadline);

  // Refuses (bad_value: Modbus 0x03) a write that would move `sensor` to the address another
  // sensor on this bus has now: both would answer it, the bus would collide, and moving one
  // back would move both. SensorWrite asks before the write is queued and again as each of
  // its settings starts.
  WriteResult check_address_free(const GatewaySensor& sensor, WriteTarget target,
                                 double value) const;

  // Lets forward() frame requests with the bus protocol's factory (driver/forwarded_exchange.h),
  // with about `max_queued` of them waiting at once (below).
  void enable_forwarding(ForwardFactory make, std::size_t max_queued = kMaxQueuedForwards);

  // Queues `pdu` for the device at `slave`, from `client` (the Modbus client's address: the
  // clients' requests are served round robin), and waits for its reply PDU. Sent once
  // (retries = 0: the client retries, and a forwarded write must never run twice) with the
  // bus's reply time-out. With `max_queued` waiting, a client is refused busy unless it has
  // fewer waiting than its share of them, so one client cannot shut the others out. A request
  // that cannot be sent before `deadline` expires.
  boost::asio::awaitable<ForwardResult> forward(std::uint8_t slave, std::vector<std::uint8_t> pdu,
                                                SteadyClock::time_point deadline,
                                                std::uint64_t client = 0);

  // Runs one transaction of a commissioning command (control/control_server.h) on the line,
  // taking turns as forwarded requests do, so every sensor keeps being polled while a command
  // scans or sets. The request is sent as given (its time-out, retries and settle time; each
  // retry a turn of its own); its framer must stay alive until this returns. One that cannot
  // be sent before `deadline` expires.
  boost::asio::awaitable<CommandExchangeResult> exchange_for_command(
      LineRequest request, SteadyClock::time_point deadline);

  // A commissioning command moved the sensor at bus address `from` to `to`: the sensor polled
  // at `from` follows it. Returns its name, or none when no sensor of this bus was at `from`.
  // `by` is who moved it, named in the log line and in the audit trail (setting "address").
  std::optional<std::string> follow_address(std::uint32_t from, std::uint32_t to,
                                            const WriteOrigin& by);
  // A commissioning command is about to move the sensor at `address`: it is not polled until
  // follow_address() or release(), or until `until` (a poll at its old address while it moves
  // would fail). A poll already on the wire finishes first: the command's next transaction
  // waits for its turn. Returns its name, or none when no sensor of this bus is there.
  std::optional<std::string> hold(std::uint32_t address, SteadyClock::time_point until);
  void release(std::uint32_t address);
  // A triggered burst (docs/monitoring.md, "Bursts"): the sensor is polled as fast as the line
  // allows until `until` (each poll due as the last one ends; the line's turns, earliest due
  // first, keep its neighbours on their schedules), then at its poll_ms again. A burst asked
  // for while one runs extends it. False when the sensor is not this bus's.
  bool burst(const GatewaySensor& sensor, SteadyClock::time_point until);
  // A commissioning command changed a setting of the sensor at `address`, with `result` as
  // the audit trail words it ("ack", "nak 0x03", "timeout"), recorded there with `by`. An
  // acknowledged one: the sensor's settings record follows (SensorDriver::note_acknowledged),
  // and the snapshot is published. Returns its name, or none when no sensor of this bus is
  // there (the change is still recorded, as the device at that address's).
  std::optional<std::string> note_setting(std::uint32_t address, WriteTarget setting,
                                          double value, const std::string& result,
                                          const WriteOrigin& by);

  // A commissioning command's transaction that may have changed the device at `address` (none:
  // not known), as control/carried_change.h words it, recorded with `by` at `unix_ms`.
  void note_carried(std::optional<std::uint32_t> address, std::string function,
                    std::string data, std::string result, std::int64_t unix_ms,
                    const WriteOrigin& by);

  const std::string& name() const { return name_; }
  BusSchedulerStats stats() const;
  // Its own counts back to zero (Gateway::reset_bus_counters()); the line's busy time and
  // restarts count on.
  void reset_counters() { stats_ = {}; }
  Line& line() { return line_.line(); }
  boost::asio::any_io_executor executor() const { return line_.executor(); }

  // Longest wait between polls of an offline sensor (line_scheduling/poll_schedule.h).
  static constexpr std::chrono::milliseconds max_backoff{5000};
  // Forwarded requests waiting per bus before clients are held to their share (a Modbus
  // connection waits for each reply, so this many means as many connections).
  static constexpr std::size_t kMaxQueuedForwards = 32;
  // How often a failing sensor held to its turn between rounds is logged, at most: once when
  // it starts, then its share of the line every interval while it goes on.
  static constexpr std::chrono::seconds kHeldLogInterval{60};
  // A sensor whose poll threw is polled again after this long.
  static constexpr std::chrono::seconds kPollFailurePause{1};

 private:
  struct Polled {
    std::shared_ptr<GatewaySensor> sensor;
    PollSchedule schedule;
    std::optional<SteadyClock::time_point> held_until{};  // hold(): not polled before then
    std::optional<SteadyClock::time_point> burst_until{};  // burst(): polled back to back
    bool removed = false;
    LineClaimant* poller = nullptr;  // its poller's, while the poller runs
    // When its wait for the round was last logged (log_held()), and its line time then.
    std::optional<SteadyClock::time_point> held_logged;
    std::chrono::nanoseconds line_time_logged{0};
    std::uint64_t failures = 0;  // polls that threw (poll_failed())
    std::optional<SteadyClock::time_point> failure_logged;
    // Its line while the bus listens, and the source it reads (listen_to()).
    std::unique_ptr<Line> heard_line;
    HeardSource* heard_from = nullptr;
  };

  // The poller of one sensor: waits for its due turn, polls, publishes, schedules the next;
  // while the bus listens, reads what was heard instead.
  boost::asio::awaitable<void> keep_polling(std::shared_ptr<Polled> polled);
  // One poll of the sensor from what was heard, published, and the wait for the next.
  boost::asio::awaitable<void> listen(Polled& polled);
  // Polls the sensor and publishes what it read.
  boost::asio::awaitable<void> poll(Polled& polled, LineClaimant& line);
  void poll_failed(Polled& polled, LineClaimant& line, std::exception_ptr failure);
  // Derives mounting, tilt and alarms once per new reading (a new sample_seq).
  void process_new_reading(GatewaySensor& sensor) const;
  // When the sensor's next poll is due: its schedule, or after a command's hold on it.
  static SteadyClock::time_point due_of(const Polled& polled);
  // Its poller waits for the poll at its (new) due time.
  void reschedule(Polled& polled);
  Polled* find_polled(std::uint32_t address);
  // A commissioning command's change, in the audit trail: the sensor's ("bus/sensor"), or
  // the device's at `address` ("bus/223") when no configured sensor is there; at `unix_ms`
  // (0: now).
  void record_command(const WriteOrigin& by, const GatewaySensor* sensor, std::uint32_t address,
                      std::string setting, std::string old_value, std::string new_value,
                      std::string result, std::int64_t unix_ms = 0) const;
  // Known offline, or its poll waits to retry after an attempt it did not answer.
  bool not_answering(const GatewaySensor& sensor) const;

  boost::asio::awaitable<ForwardResult> exchange(LineClaimant& line, std::uint8_t slave,
                                                 const std::vector<std::uint8_t>& pdu);
  // Whether `client` may queue one more forwarded request now.
  bool forward_admitted(std::uint64_t client) const;

  // One log line when a failing sensor starts waiting for the round's polls, then at most
  // every kHeldLogInterval with its share while it goes on.
  void log_held(const GatewaySensor& sensor, SteadyClock::time_point now);

  SharedLine line_;
  std::string name_;
  AuditTrail* audit_ = nullptr;
  std::vector<std::shared_ptr<Polled>> sensors_;
  ForwardFactory make_forward_ = nullptr;
  std::size_t max_queued_forwards_ = kMaxQueuedForwards;
  bool retiring_ = false;  // retire(): the queued writes, then stop
  HeardSource* heard_ = nullptr;  // listen_to()
  std::function<bool()> clock_synchronised_;  // set_clock_check()
  BusSchedulerStats stats_;  // but busy, which the line keeps
};

}  // namespace tiltgate
