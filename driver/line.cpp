#include "driver/line.h"

namespace tiltgate {

const char* to_string(LineError e) {
  switch (e) {
    case LineError::timeout: return "time-out";
    case LineError::io: return "port I/O error";
    case LineError::closed: return "port not open";
    case LineError::cancelled: return "cancelled";
    case LineError::expired: return "not sent: its deadline would pass first";
    case LineError::overloaded: return "the machine held the reply back: overloaded";
  }
  return "unknown";
}

}  // namespace tiltgate
