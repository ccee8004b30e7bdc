// The Rieker Flex driver: turns polls and register writes into Rieker transactions.
// Reads angles (type 4 on an H6, type 1 on an H4360), reads identity after start and after
// every reconnect, and does the lock dance around every setting (unlock, command, check the
// ACK, lock again) so the caller never sees lock levels. A write the sensor stopped answering
// is answered at once; the sensor is locked again at the next poll that reaches it.
#pragma once

#include <boost/asio/awaitable.hpp>

#include "driver/polled_sensor_driver.h"
#include "rieker/codec.h"

namespace tiltgate::rieker {

struct RiekerDriverOptions {
  std::string name = "sensor";  // for log lines
  Model model = Model::h6;
  std::uint16_t address = kFactoryAddress;
  std::uint16_t master_address = 0;
  int busy_retries = 3;  // NAK 5 "busy, wait and try again": this many more tries
  std::chrono::milliseconds busy_wait{20};
  ReplyTimeouts reply_timeouts;  // the bus's timeout_ms and max_timeout_ms
};

// Why one exchange produced no usable reply.
struct ExchangeError {
  enum class Kind { line, nak, bad_reply } kind;
  LineError line = LineError::timeout;
  std::uint8_t nak = 0;
  std::string detail;
};

class RiekerDriver : public PolledSensorDriver {
 public:
  explicit RiekerDriver(RiekerDriverOptions options);

  std::string_view model() const override;
  WriteResult check_write(WriteTarget target, double value) const override;
  boost::asio::awaitable<WriteResult> write(Line& line, WriteTarget target, double value) override;

  void follow_address(std::uint32_t address) override;
  // The protocol reads no setting back (the vendor's function list has no Get for the filter,
  // the zero or the baud): the acknowledged value is kept.
  void note_acknowledged(WriteTarget target, double value) override;
  // "NAK 2 (function not valid for this sensor or mode)".
  std::string refusal_text(std::uint8_t code) const override;

  std::uint16_t address() const { return options_.address; }

 protected:
  boost::asio::awaitable<bool> read_identity(Line& line) override;
  boost::asio::awaitable<void> read_measurement(Line& line) override;  // Get Angle
  const std::string& log_name() const override { return options_.name; }
  const char* kind() const override { return "sensor"; }

 private:
  // One request and its reply, with counters kept. A NAK 5 is retried after a pause.
  boost::asio::awaitable<Expected<Frame, ExchangeError>> exchange(Line& line, RequestResult request,
                                                                  ExchangeOptions options = {});
  // The setting itself, between unlock and lock.
  boost::asio::awaitable<WriteResult> apply(Line& line, WriteTarget target, double value);
  boost::asio::awaitable<WriteResult> set_address(Line& line, std::uint16_t new_address);
  // Lock level 0 again after a write, whatever became of it; a failure is only logged, and
  // one without an answer is tried again at the next poll (relock_owed_). True when locked.
  boost::asio::awaitable<bool> lock_again(Line& line);
  Route route() const { return Route{options_.address, options_.master_address}; }
  AngleType angle_type() const;

  RiekerDriverOptions options_;
  // A write ended without the sensor answering (or out of time) after it may have unlocked
  // it: the next poll locks it before it measures.
  bool relock_owed_ = false;
};

// An ExchangeError as the write error the gateway maps to a Modbus exception.
WriteError to_write_error(const ExchangeError& error, std::string_view step);

}  // namespace tiltgate::rieker
