// The poll cycle every sensor family shares, so each driver writes only its protocol: identity
// first whenever it is unknown on this line (after start, a reconnect of the tty, a restart),
// then one measurement; and one log line when the sensor stops or starts answering.
//
// Who answers is checked too: the identity is read again when a sensor answers after a silence
// (a sensor swapped in the field goes through one: its cable is unplugged), and a serial that
// differs from the configured one ([[sensor]] serial) makes the device the wrong one: no
// measurement is taken of it, and each poll reads its identity again instead, until the
// configured serial answers (SensorState::wrong_device). Without a configured serial a changed
// serial is only warned about.
//
// Every exchange also goes through here, with the sensor's own reply time-out
// (driver/adaptive_reply_timeout.h), which the Line's timing adapts after every attempt: the
// retries are made here, each attempt a transaction of the Line's, so a sensor whose first
// reply came late gets its retry with the longer wait, and a gateway's bus can give the line
// to the other sensors between two attempts (line_scheduling/line_claimant.h). A sensor that is
// offline is probed without retries: each retry after a time-out costs the bus the late-reply
// guard too, and the scheduler already tries again after its back-off.
#pragma once

#include <boost/asio/awaitable.hpp>
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "driver/adaptive_reply_timeout.h"
#include "driver/sensor_driver.h"

namespace tiltgate {

// Per-exchange overrides of the bus settings a driver may ask for.
struct ExchangeOptions {
  int retries = -1;  // -1: the bus's
  std::chrono::milliseconds settle{0};
};

class PolledSensorDriver : public SensorDriver {
 public:
  boost::asio::awaitable<void> poll(Line& line) final;
  const SensorState& state() const final { return state_; }
  void reset_counters() final { state_.counters = {}; }
  // Reads the settings back at the next poll (read_settings()). A family that cannot read a
  // setting back overrides this to record `value` as acknowledged.
  void note_acknowledged(WriteTarget target, double value) override;
  void expect_serial(std::string serial) final { expected_serial_ = std::move(serial); }

 protected:
  explicit PolledSensorDriver(ReplyTimeouts timeouts);

  // Reads serial, firmware and the like, then calls identity_read_on(generation seen before
  // the first request). False when the sensor did not answer at all (the poll then fails).
  virtual boost::asio::awaitable<bool> read_identity(Line& line) = 0;
  // One measurement: a new Reading and polls_ok, or polls_failed.
  virtual boost::asio::awaitable<void> read_measurement(Line& line) = 0;
  // Reads the settings the protocol can read back into state_.settings (those it cannot keep
  // their last acknowledged value). Called after the identity, and before the next measurement
  // after a return from offline (the sensor may have been changed or replaced meanwhile) and
  // after note_acknowledged(). False when the sensor did not answer at all.
  virtual boost::asio::awaitable<bool> read_settings(Line& line);
  // For log lines: the configured sensor name and what it is ("sensor", "module").
  virtual const std::string& log_name() const = 0;
  virtual const char* kind() const = 0;

  // One request/reply on the line, keeping the counters every driver keeps the same way:
  // transactions, time-outs, port errors, late replies, and online (whether anything valid
  // came back). Sends the request with the sensor's reply time-out, adapted after each
  // attempt; `options.retries` -1 retries as the line's retries() says. A request the line
  // did not send (LineError::expired), one a stop cut off (LineError::cancelled) or one the
  // machine held back (LineError::overloaded) changes nothing of the sensor's state.
  boost::asio::awaitable<Expected<Done, LineError>> transact_counted(Line& line,
                                                                    LineRequest request,
                                                                    ExchangeOptions options);

  // The identity was read (or found unreadable) on this line generation: not again until the
  // line reopens or forget_identity().
  void identity_read_on(std::uint64_t generation) { identity_generation_ = generation; }
  // After a restart or reset: read the identity again at the next poll.
  void forget_identity() {
    state_.identity_known = false;
    identity_generation_ = 0;
  }

  // The identity being read is the wrong device's again (it answers each poll while it stays):
  // the family's log line about who answers is not repeated.
  bool rechecking_wrong_device() const { return rechecking_wrong_device_; }

  SensorState state_;

 private:
  // After an identity read: compares the serial read with the configured one (and the one read
  // before), sets wrong_device and logs what changed.
  void check_serial();

  // Adapts the reply time-out to the Line's timing of one exchange; logs when that changes.
  void note_timing(const LineTiming& timing, const std::string& line_name);
  // One attempt of an exchange into the counters (requests, replies, bytes).
  void count_attempt(const Expected<Done, LineError>& sent, const LineTiming& timing);

  std::uint64_t identity_generation_ = 0;
  // read_settings() is due at the next poll: the sensor came back from offline, or someone
  // else changed a setting.
  bool settings_owed_ = false;
  AdaptiveReplyTimeout reply_timeout_;
  // When "answers late" was last logged at warning: a sensor that goes late and back under load
  // is warned of once in kLateWarningInterval, the rest at debug (docs/operations.md, "How the gateway behaves").
  std::optional<SteadyClock::time_point> late_warned_;
  bool late_logged_ = false;  // the last "answers late" was logged at warning
  bool probing_ = false;  // in a poll of a sensor that was offline: no retries
  std::string expected_serial_;  // [[sensor]] serial; empty: any device is served
  std::string last_serial_;      // the serial read last (empty before the first)
  bool rechecking_wrong_device_ = false;
  // Its identity is to be read again before its next measurement: it was silent.
  bool identity_owed_ = false;
  // Reading the identity of a sensor that was not online: an answer does not make it online
  // yet (its measurement, or its being the wrong device, does).
  bool holding_online_ = false;
};

}  // namespace tiltgate
