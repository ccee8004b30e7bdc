// What a commissioning command reports while it works. The engine's coroutines (a scan, a raw
// request, info, watch, set: commission/*_engine.h) never print: each front end shows
// these events its own way (the command line as text, commission/event_text.h; the web console
// as JSON, console/bus_actions.h), so rewording a line of text breaks no other front end.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "commission/poll_outcome.h"
#include "commission/scan_plan.h"

namespace tiltgate {

// Something worth telling that is not a result, e.g. "--broadcast works only with one sensor".
struct NoteEvent {
  bool warning = false;
  std::string text;
};

// How far a scan is: probes done of the total, at the rate being tried, and what answered so far.
struct ProgressEvent {
  std::size_t done = 0;
  std::size_t total = 0;
  std::uint32_t baud = 0;
  std::vector<FoundSensor> found;
};

// A device that answered a scan's probe, with what its family's driver read of it.
struct DeviceFoundEvent {
  FoundSensor sensor;
};

// A scan's end: every address that answered (the same sensor at several rates once), how many
// probes it took and how long, and the configuration of the sensors found.
struct ScanFinishedEvent {
  std::vector<FoundSensor> found;
  std::vector<RepeatedSensor> repeated;
  std::size_t probes = 0;
  std::chrono::milliseconds took{0};
  std::string configuration;  // as `scan --config-out` writes it
  std::vector<SensorTable> tables;
};

// One request of the command's own making (`raw`) and its reply, byte for byte.
struct ExchangeEvent {
  std::vector<std::uint8_t> sent;
  std::size_t address_bytes = 0;  // leading bytes of `sent` sent with the 9th bit set
  bool answered = false;
  std::vector<std::uint8_t> received;  // the reply, checksum included, when answered
  std::string verdict;                 // the checksum's verdict on it, e.g. "CRC ok"
  std::string rejected_verdict;        // unanswered: why bytes that came were not a reply
  std::string decoded;                 // the reply in words
  bool refused = false;                // the device refused the request (a NAK, an exception)
};

// A sensor as a command found it: what it told of itself and what its last poll came to. What
// `info` shows of each sensor (and `set` after a change) and `watch` in each row.
struct SensorReadingEvent {
  std::uint32_t address = 0;
  std::string model;         // the model it is polled as; empty: a device without its driver
  std::string device_model;  // its own name for its model, where it reports one
  std::string serial;        // empty: not told
  std::string firmware;      // empty: not told
  std::optional<std::uint16_t> lock_level;
  PollResult result = PollResult::silent;  // what the last poll came to
  std::string status;                      // the same in words: "ok", "no reply", "refused: ..."
  std::optional<double> angle_x;           // the last reading's; none before the first
  std::optional<double> angle_y;           // none on single-axis sensors too
  std::optional<std::chrono::milliseconds> age;   // of the last reading, when polled
  std::optional<double> readings_per_second;      // `watch`: none before its second reading
  std::chrono::system_clock::time_point polled;   // when the poll ended
  std::string self_report;  // a device without its driver: what it said, one "name: value" line each
};

// One round of `watch` over every sensor: each one's reading (also reported one by one as it
// came), and what there is to say of each (the model found, why it gave no reading; empty:
// nothing), in the order of the sensors.
struct WatchRoundEvent {
  int round = 0;
  std::vector<SensorReadingEvent> readings;
  std::vector<std::string> notes;
};

// A sensor's answer to one write of `set`. `result`: "ack", "nak" (refused; `refusal_code` the
// protocol's code where it gave one), "timeout", or "failed" (never sent, or the sensor stayed
// busy; `detail` says why).
struct SettingAcknowledgedEvent {
  std::uint32_t address = 0;
  std::string setting;                 // the setting's name in the model's descriptor
  std::optional<double> old_value;     // as last read from the sensor; none: not known
  double value = 0;
  std::string result;
  std::optional<std::uint8_t> refusal_code;
  std::string detail;
};

// Every write of a `set` acknowledged: the setting as the engineer named it, at the sensor's
// address then.
struct SettingAppliedEvent {
  std::string setting;  // e.g. "filter 5"
  bool permanent = false;
  std::uint32_t address = 0;
};

// A sensor `set` moved to another address. `gateway_sensor`: the running gateway that owns the
// bus polls it, under that name, at the new address from now on; empty: no gateway follows it.
struct AddressMovedEvent {
  std::uint32_t from = 0;
  std::uint32_t to = 0;
  std::string gateway_sensor;
};

// A sensor `set` restarted; at a new rate `baud`, which the command's line followed
// (`line_follows`), or not: a running gateway's bus stays at `bus_baud`.
struct SensorRestartedEvent {
  std::optional<std::uint32_t> baud;
  bool line_follows = true;
  std::uint32_t bus_baud = 0;
};

// The configuration file the sensor came from now follows what `set` moved: one line each.
struct ConfigUpdatedEvent {
  std::string file;
  std::vector<std::string> changes;  // "updated FILE: sensor NAME address 223 -> 7"
};

// A setting's value as read back after `set`; none: the sensor did not tell it.
struct SettingValue {
  std::string name;
  std::optional<double> value;
};

// The values `set` wrote, as the sensor reads them back.
struct SettingsReadEvent {
  std::uint32_t address = 0;
  std::vector<SettingValue> settings;
};

// A running gateway that owns the bus could not be told of a change made through it: what it
// will do instead (its polls may fail while a sensor moves, its registers show an old value).
struct GatewayWarningEvent {
  std::string text;
};

// Why the command could not do what was asked; `exit_code` 1 (the bus or the sensor) or 2 (the
// request itself).
struct FailedEvent {
  int exit_code = 1;
  std::string message;
};

using CommissionEvent =
    std::variant<NoteEvent, ProgressEvent, DeviceFoundEvent, ScanFinishedEvent, ExchangeEvent,
                 FailedEvent, SensorReadingEvent, WatchRoundEvent, SettingAcknowledgedEvent,
                 SettingAppliedEvent, AddressMovedEvent, SensorRestartedEvent, ConfigUpdatedEvent,
                 SettingsReadEvent, GatewayWarningEvent>;

// Where a command's events go, in the order they happen.
using EventSink = std::function<void(const CommissionEvent&)>;

}  // namespace tiltgate
