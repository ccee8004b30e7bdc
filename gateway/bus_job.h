// What a bus carries out for someone who waits for the answer: a Modbus write to one of its
// sensors (SensorWrite), a request forwarded to a device it passes through, or one
// transaction of a commissioning command (the control socket). BusQueue keeps the jobs in the
// order the bus takes them up; BusScheduler carries them out.
#pragma once

#include <boost/asio/any_io_executor.hpp>
#include <boost/asio/steady_timer.hpp>
#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

#include "driver/expected.h"
#include "driver/line.h"
#include "gateway/sensor_write.h"

namespace tiltgate {

// A Modbus request for the device at `slave` on a bus that passes it through: its PDU.
struct ForwardRequest {
  std::uint8_t slave;
  std::vector<std::uint8_t> pdu;
};

// Why a forwarded request got no reply PDU to relay.
enum class ForwardFailure {
  busy,         // the bus's forward queue was full (Modbus 0x06)
  expired,      // still queued at its deadline (0x0B)
  no_response,  // sent, but no reply: time-out, port closed or failed; or stopping (0x0B)
  unframed,     // the bus's protocol cannot frame it, or cannot forward at all (0x04)
};
const char* to_string(ForwardFailure failure);

// The reply PDU (function code and data, exception replies included) or why there is none.
using ForwardResult = Expected<std::vector<std::uint8_t>, ForwardFailure>;

// One transaction of a commissioning command, sent as given (its time-out, retries and settle
// time); its framer stays alive until it is answered.
struct CommandTransaction {
  LineRequest request;
};

// What a commissioning command's transaction through the control socket came to: the Line's
// outcome, its timing and generation, as the command's own Line would report them.
struct CommandExchangeResult {
  Expected<Done, LineError> done = Done{};
  bool expired = false;  // never sent: still queued at its deadline
  LineTiming timing;
  std::uint64_t generation = 0;
};

// The work of a job, and its answer: the same alternative of each.
using BusWork = std::variant<SensorWrite, ForwardRequest, CommandTransaction>;
using BusAnswer = std::variant<WriteResult, ForwardResult, CommandExchangeResult>;

// The answer to a job the bus does not carry out because it stops (or, for forwarded requests
// and commands, retires): never sent.
BusAnswer refusal(const BusWork& work);
// The answer to a job still queued at its deadline: never sent.
BusAnswer expiry(const BusWork& work);

// One job on its way through the bus, and the answer its caller waits for.
struct BusJob {
  BusJob(boost::asio::any_io_executor executor, BusWork work)
      : work(std::move(work)), done(executor) {}

  void answer_with(BusAnswer answer) {
    this->answer = std::move(answer);
    done.cancel();
  }

  BusWork work;
  std::optional<BusAnswer> answer;
  boost::asio::steady_timer done;  // its waiter's: cancelled when the answer is set
};

}  // namespace tiltgate
