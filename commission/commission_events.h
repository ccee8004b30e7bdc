// What a commissioning command reports while it works. The engine's coroutines (a scan, a raw
// request: commission/scan_engine.h, commission/raw_engine.h) never print: each front end shows
// these events its own way (the command line as text, commission/event_text.h; the web console
// as JSON, console/bus_actions.h), so rewording a line of text breaks no other front end.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <variant>
#include <vector>

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

// Why the command could not do what was asked; `exit_code` 1 (the bus or the sensor) or 2 (the
// request itself).
struct FailedEvent {
  int exit_code = 1;
  std::string message;
};

using CommissionEvent = std::variant<NoteEvent, ProgressEvent, DeviceFoundEvent,
                                     ScanFinishedEvent, ExchangeEvent, FailedEvent>;

// Where a command's events go, in the order they happen.
using EventSink = std::function<void(const CommissionEvent&)>;

}  // namespace tiltgate
