#include "gateway/unit_diagnostics.h"

#include <algorithm>

#include "modbus_tcp/diagnostics.h"

namespace tiltgate {

namespace {

std::uint16_t wrapped(std::uint64_t count) { return std::uint16_t(count & 0xFFFF); }

}  // namespace

std::optional<std::uint16_t> diagnostic_count(const SensorCounters& c, std::uint16_t sub_function) {
  switch (sub_function) {
    case diagnostic::bus_message_count:
      return wrapped(std::uint64_t(c.requests) + c.replies + c.garbled + c.late_replies);
    case diagnostic::bus_communication_error_count:
      // A garbled attempt failed its checksum or its framing; a checksum error can also come
      // before a valid reply in one attempt: the larger of the two misses neither.
      return wrapped(std::max(c.garbled, c.checksum_errors));
    case diagnostic::bus_exception_error_count: return wrapped(c.refused);
    case diagnostic::server_message_count: return wrapped(c.requests);
    case diagnostic::server_no_response_count: return wrapped(c.no_reply);
    case diagnostic::server_nak_count: return wrapped(c.refused - std::min(c.busy, c.refused));
    case diagnostic::server_busy_count: return wrapped(c.busy);
    case diagnostic::bus_character_overrun_count: return wrapped(c.overruns);
    default: return std::nullopt;
  }
}

CommEventCounter comm_event_counter(const SensorCounters& counters) {
  return CommEventCounter{0x0000, wrapped(counters.replies)};
}

void add_counts(SensorCounters& total, const SensorCounters& c) {
  total.requests += c.requests;
  total.replies += c.replies;
  total.garbled += c.garbled;
  total.no_reply += c.no_reply;
  total.late_replies += c.late_replies;
  total.checksum_errors += c.checksum_errors;
  total.refused += c.refused;
  total.busy += c.busy;
  total.overruns += c.overruns;
  total.uart_errors += c.uart_errors;
  total.bytes_out += c.bytes_out;
  total.bytes_in += c.bytes_in;
}

}  // namespace tiltgate
