// One change made to the plant, through any door: what the audit trail keeps (audit/), so that a
// controls engineer can tell who changed a sensor, when, through what, and what came of it.
// Plain data.
#pragma once

#include <cstdint>
#include <string>

namespace tiltgate {

// Who asked for a change, and through which door. Each door fills in `who` in its own words:
//   door "modbus":         "10.0.0.5:50122", or over TLS "10.0.0.5:50122 (CN=plc-1,O=Plant)"
//   door "control socket": "user root (uid 0, pid 4242)" (SO_PEERCRED, control/peer_identity.h)
//   door "sparkplug":      "host SCADA-1" (the primary host id), or "a DCMD" without one
//   door "console":        the console user's name, "alice"
struct WriteOrigin {
  std::string door;
  std::string who;

  bool operator==(const WriteOrigin&) const = default;
};

struct AuditRecord {
  std::int64_t unix_ms = 0;  // when the result was known, wall clock
  WriteOrigin origin;
  std::string sensor;     // "bus/sensor"; empty when the change is not one sensor's (a config)
  std::string setting;    // the map's setting name ("filter", "zero", "address"), or an action:
                          // "scan", "raw", "config", "login"
  std::string old_value;  // empty: not known
  std::string new_value;
  // "ack"; "nak 0x03" (the sensor's refusal code); "timeout"; "refused: WHY" (never sent: a
  // role, a range, another device at the address); "error: WHY"; "ok" for an action.
  std::string result;

  bool operator==(const AuditRecord&) const = default;
};

}  // namespace tiltgate
