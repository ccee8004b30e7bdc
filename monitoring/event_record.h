// One event of the monitoring (docs/monitoring.md, "Events"): an alarm that set or cleared, a
// baseline changed, a sensor that went offline or came back, another device answering in a
// sensor's place. As JSON it is what `GET /api/events` answers (newest first), the MQTT event
// topic carries, and the event log keeps on disk, one object each:
//
//   {"seq": 12, "time": "2026-12-07T10:15:02.250Z", "unix_ms": 1796638502250,
//    "sensor": "mast", "kind": "alarm", "alarm": "x_high", "level": "warning",
//    "state": "set", "value": 2.31, "threshold": 2.0}
//
// "alarm", "level", "value" and "threshold" belong to alarms; a baseline's event has "value"
// {"x", "y"} and "previous" {"x", "y"} and "by" (who set it); offline, online, wrong_device
// and burst have "text" (why, the serial heard, a burst's trigger and record). "state" is
// "set" or "clear" for alarms and wrong_device, "start" or "end" for a burst, absent otherwise.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace tiltgate::monitoring {

struct EventRecord {
  std::uint64_t seq = 0;      // the log's own number, 1 for its first event, never reused
  std::int64_t unix_ms = 0;   // when it happened (an alarm's: its reading's time), UTC
  std::string sensor;
  std::string kind;  // "alarm", "baseline", "offline", "online", "wrong_device", "burst"
  std::string alarm;          // alarms: "x_high", ... (line_scheduling/alarm_tracker.h)
  std::string level;          // alarms: "warning" or "danger"
  std::string state;          // "set" or "clear" (alarms, wrong_device); "start", "end"
  std::optional<double> value;      // alarms: the value at that reading
  std::optional<double> threshold;  // alarms: the level's threshold
  // Baselines: the new and the previous reference, and who set it.
  std::optional<double> x, y, previous_x, previous_y;
  std::string by;
  std::string text;           // offline, online, wrong_device: in words

  bool operator==(const EventRecord&) const = default;
};

std::string event_json(const EventRecord& event);
// None for text that is no event object (a damaged record).
std::optional<EventRecord> event_from_json(std::string_view text);

}  // namespace tiltgate::monitoring
