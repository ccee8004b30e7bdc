// A command's Line on a bus the gateway serves: how a commissioning command the gateway runs
// for someone (the web console's scan and raw frames; a command line's request through the
// control socket, control/command_runner.h) talks to that bus's sensors. Each
// attempt of a transaction is a turn of the line's spare time (BusScheduler::
// exchange_for_command: every sensor keeps being polled meanwhile; control/attempt_turns.h).
//
// What the command may change is recorded in the audit trail from what the gateway carried and
// got back (control/carried_change.h), under the door and person in `by`: a transaction the
// bus's protocol reads as a change waits for the engine's report of it (a setting
// acknowledged, a sensor moved), which then stands for it as one record; anything else records
// it as it is. With [audit] when_full = "refuse" and the disk refusing, such a transaction is
// refused before it is sent, and recorded.
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "audit/audit_record.h"
#include "capture/black_box.h"
#include "config/config.h"
#include "control/carried_change.h"
#include "control/attempt_turns.h"
#include "driver/line.h"
#include "driver/write_target.h"
#include "line_scheduling/bus_scheduler.h"

namespace tiltgate {

// A bus as the gateway serves it to commands.
struct ServedBus {
  BusConfig config;
  std::shared_ptr<BusScheduler> scheduler;  // held while a command may use it
  // Reads what a command's transaction asks of a device, for the audit trail.
  const ProtocolDescriptor* protocol = nullptr;
  // What its line carried lately (capture/black_box.h): what `tiltgate capture` reads.
  std::shared_ptr<BlackBox> black_box{};
};

class Gateway;

// The buses the gateway serves now, as commands may use them. On the buses' executor.
std::vector<ServedBus> served_buses(const Gateway& gateway);
std::optional<ServedBus> served_bus(const Gateway& gateway, const std::string& name);

class ServedBusLine final : public Line {
 public:
  ServedBusLine(ServedBus bus, WriteOrigin by);
  // Records a change still waiting for its report, and polls again any sensor the command held.
  ~ServedBusLine() override;
  ServedBusLine(const ServedBusLine&) = delete;
  ServedBusLine& operator=(const ServedBusLine&) = delete;

  boost::asio::awaitable<Expected<Done, LineError>> transact(LineRequest request) override;
  std::uint64_t generation() const override { return generation_; }
  bool is_open() const override { return !stopped_; }
  int retries() const override { return defaults_.retries; }
  const std::string& name() const override { return bus_.config.name; }
  const LineStats& stats() const override { return stats_; }
  const LineTiming& last_timing() const override { return timing_; }

  // What a request that leaves them to the bus gets (control/attempt_turns.h).
  void set_defaults(CommandLineDefaults defaults) { defaults_ = defaults; }
  // How long a transaction may wait for its turn on a busy bus.
  static constexpr std::chrono::seconds kQueueDeadline{10};
  // The longest a command may keep the gateway from polling a sensor it is re-addressing.
  static constexpr std::chrono::seconds kMaxHold{10};

  const ServedBus& bus() const { return bus_; }
  // Whether the latest attempt was refused before it was sent, for the audit trail's disk
  // ([audit] when_full = "refuse"): the command says so instead of "no reply".
  bool last_audit_refused() const { return audit_refused_; }
  // The command's reports. Each returns the configured sensor ("bus/sensor") it concerned, or
  // none when the gateway polls no sensor there.
  // It is about to move the sensor at `address`: not polled until follow(), the
  // command's end, or kMaxHold.
  std::optional<std::string> hold(std::uint32_t address);
  // It moved the sensor from `from` to `to`: polled there from now on. The move's own record
  // stands for the transaction that made it.
  std::optional<std::string> follow(std::uint32_t from, std::uint32_t to);
  // The sensor at `address` answered a change of `setting` to `value` with `result` ("ack",
  // "nak 0x03", "timeout"): recorded as the change the latest transaction carried, and an
  // acknowledged one kept in the sensor's settings record.
  std::optional<std::string> setting_changed(std::uint32_t address, WriteTarget setting,
                                             double value, std::string result);
  // Something else came between a change and its report: the change is recorded as it is.
  void record_pending();
  // Every later transaction is cancelled.
  void stop() { stopped_ = true; }

 private:
  boost::asio::awaitable<Expected<Done, LineError>> attempt(const LineRequest& request);
  // Holds the change a request asks until its report; when the audit trail refuses changes,
  // records it as refused and returns false.
  bool note_asked(control::CarriedChange asked);

  ServedBus bus_;
  WriteOrigin by_;
  CommandLineDefaults defaults_;
  bool stopped_ = false;
  bool audit_refused_ = false;
  std::uint64_t generation_ = 1;
  LineStats stats_;
  LineTiming timing_;
  std::vector<std::uint32_t> held_;
  // The change the latest changing transaction carried, until a report names it or it is
  // recorded as it is. Reads in between (a read-back, the lock) leave it waiting; the same
  // request again (the command's retry) replaces it.
  std::optional<control::CarriedChange> change_;
};

}  // namespace tiltgate
