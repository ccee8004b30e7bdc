#include "gateway/bus_job.h"

namespace tiltgate {

namespace {

CommandExchangeResult failed_exchange(LineError error) {
  CommandExchangeResult result;
  result.done = Unexpected{error};
  return result;
}

}  // namespace

const char* to_string(ForwardFailure failure) {
  switch (failure) {
    case ForwardFailure::busy: return "bus too busy: forward queue full";
    case ForwardFailure::expired: return "bus too busy: not sent in time";
    case ForwardFailure::no_response: return "no reply";
    case ForwardFailure::unframed: return "cannot be forwarded on this bus";
  }
  return "unknown";
}

BusAnswer refusal(const BusWork& work) {
  if (const auto* write = std::get_if<SensorWrite>(&work))
    return write->fail(WriteError{WriteErrorKind::no_response, "gateway stopping"});
  if (std::holds_alternative<ForwardRequest>(work))
    return ForwardResult{Unexpected{ForwardFailure::no_response}};
  return failed_exchange(LineError::cancelled);
}

BusAnswer expiry(const BusWork& work) {
  if (const auto* write = std::get_if<SensorWrite>(&work))
    return write->fail(WriteError{WriteErrorKind::busy, "bus too busy: write not started in time"});
  if (std::holds_alternative<ForwardRequest>(work))
    return ForwardResult{Unexpected{ForwardFailure::expired}};
  CommandExchangeResult expired = failed_exchange(LineError::timeout);
  expired.expired = true;
  return expired;
}

}  // namespace tiltgate
