#include "line_scheduling/bus_answers.h"

namespace tiltgate {

const char* to_string(ForwardFailure failure) {
  switch (failure) {
    case ForwardFailure::busy: return "bus too busy: forward queue full";
    case ForwardFailure::expired: return "bus too busy: not sent in time";
    case ForwardFailure::no_response: return "no reply";
    case ForwardFailure::unframed: return "cannot be forwarded on this bus";
    case ForwardFailure::standby: return "not sent: this gateway is the standby";
  }
  return "unknown";
}

}  // namespace tiltgate
