#include "gateway/serial_options.h"

namespace tiltgate {

SerialLineOptions serial_options_from(FamilyList families, const BusConfig& bus) {
  SerialLineOptions o;
  o.name = bus.name;
  o.port = bus.port;
  o.baud = bus.baud;
  o.timeout = bus.timeout;
  o.retries = bus.retries;
  o.late_guard = bus.late_guard;
  o.gap = bus.gap;
  o.rs485_kernel = bus.rs485_kernel;
  o.echo = bus.echo;
  o.low_latency = bus.low_latency;
  o.reopen_min = bus.reopen_min;
  o.reopen_max = bus.reopen_max;
  // The loader accepts only the families' protocols; 8N1 is the transport's own default.
  if (const ProtocolEntry protocol = find_protocol(families, bus.protocol); protocol.protocol) {
    o.framing = protocol.protocol->framing;
    o.replies_name_sender = protocol.protocol->replies_name_sender;
  }
  // A bus that chose its own framing (its parity and stop_bits keys) overrides it.
  if (bus.framing) o.framing = *bus.framing;
  return o;
}

}  // namespace tiltgate
