// What the gateway knows about one sensor: the cache that Modbus reads are answered from.
// Drivers fill it; the register map reads it. Vendor-neutral by design.
#pragma once

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "driver/write_target.h"

namespace tiltgate {

using SteadyClock = std::chrono::steady_clock;

// One measurement, taken in one poll. A Modbus read sees all of it or none of it.
struct Reading {
  double angle_x = NAN;                 // degrees (single-axis sensors: their one axis)
  double angle_y = NAN;                 // degrees, NaN on single-axis sensors
  std::optional<std::int32_t> raw_counts;       // sensors that report raw counts
  std::optional<std::int32_t> raw_temperature; // sensors that report a temperature
  // Degrees Celsius where the sensor reports a temperature, as its driver converts it
  // (docs/monitoring.md, "Temperature").
  std::optional<double> temperature_c;
  SteadyClock::time_point taken{};     // when the reply arrived
  // The sensor's own values (driver/device_value.h), in its list's order; NaN for one that
  // could not be read in this poll.
  std::vector<double> device_values;
};

// The bounds of the reply-time histogram (SensorCounters::reply_buckets), milliseconds; one
// more bucket counts the replies beyond the last.
inline constexpr std::array<int, 11> kReplyBucketsMs = {1, 2, 5, 10, 20, 50, 100, 200, 500,
                                                        1000, 2000};

// Counters a field engineer reads when a bus misbehaves.
struct SensorCounters {
  std::uint32_t transactions = 0;   // request/reply exchanges started, retries not counted
  // Each attempt of those exchanges, retries included (docs/diagnostics.md): requests written;
  // valid replies taken (refusals included); replies heard that made no valid frame (a broken
  // checksum, a wrong length, a collision); attempts that heard nothing at all in time.
  std::uint32_t requests = 0;
  std::uint32_t replies = 0;
  std::uint32_t garbled = 0;
  std::uint32_t no_reply = 0;
  // Bytes of its exchanges written and read (late replies and garbled ones included).
  std::uint64_t bytes_out = 0;
  std::uint64_t bytes_in = 0;
  // What the gateway's UART counted wrong while the sensor's replies came (a tty's TIOCGICOUNT;
  // ports that cannot count leave both 0): characters lost to overruns, characters with a
  // framing or parity error (a wrong rate or parity, noise).
  std::uint32_t overruns = 0;
  std::uint32_t uart_errors = 0;
  std::uint32_t polls_ok = 0;       // measurement polls that produced a reading
  std::uint32_t polls_failed = 0;   // measurement polls that did not
  std::uint32_t timeouts = 0;       // exchanges that got no valid reply in time
  std::uint32_t checksum_errors = 0;  // replies dropped for a bad CRC/LRC
  std::uint32_t io_errors = 0;      // exchanges lost to a port failure
  // Replies (or stray bytes) that arrived after the reply time-out: discarded, never taken as
  // the answer to a later request.
  std::uint32_t late_replies = 0;
  // Requests the sensor refused, by the refusal code its protocol gives (a negative
  // acknowledgement's code; codes past the end are not counted), and the last such code.
  std::array<std::uint32_t, 8> refusals{};
  std::optional<std::uint8_t> last_refusal;
  // Every refusal, whatever its code, and those of them that said the device was busy (the
  // family's driver knows its protocol's busy code): the rest are NAKs (FC 08's counts,
  // docs/diagnostics.md).
  std::uint32_t refused = 0;
  std::uint32_t busy = 0;
  // Times another device than the configured serial was found answering in its place.
  std::uint32_t wrong_device_found = 0;
  // The longest a reply took since start, from the end of its request to its last byte, as
  // the line waited for it (what this machine held it back included: the line's timing, not
  // the sensor's alone).
  std::chrono::milliseconds slowest_reply{0};
  // Every reply's time, as slowest_reply's, by the first bound of kReplyBucketsMs it is within
  // (whole milliseconds, rounded up), and their sum.
  std::array<std::uint32_t, kReplyBucketsMs.size() + 1> reply_buckets{};
  std::uint64_t reply_ms_sum = 0;
};

struct SensorState {
  std::optional<Reading> reading;   // the last good measurement
  std::uint16_t sample_seq = 0;     // +1 for every new reading (wraps)
  bool online = false;              // the last exchange with the sensor got a valid reply
  // Its last exchange got no valid reply in time, on a port that worked: the sensor's own
  // doing (silent, garbled, late), not a tty gone.
  bool unanswered = false;
  // When the sensor last gave a valid reply (a refusal included); none before the first.
  std::optional<SteadyClock::time_point> last_answer;
  bool identity_known = false;      // serial/firmware read since the last (re)connect
  bool last_write_failed = false;
  // The sensor has answered after the reply time-out recently (status bit 5); its time-out
  // is being adapted upward (reply_timeout).
  bool answers_late = false;
  // The reply time-out in use for this sensor now: the bus's, or more after late replies
  // (never above the bus's maximum). Zero until the driver has exchanged anything.
  std::chrono::milliseconds reply_timeout{0};
  std::string serial;               // as the sensor reports it, trailing spaces trimmed
  // The device answering at the sensor's address reported another serial than the configured
  // one ([[sensor]] serial): it is not that sensor, so nothing of it is served as the sensor's
  // (no readings taken, no writes sent) until the configured serial answers again (status bit 6).
  bool wrong_device = false;
  // The gateway is the standby of a redundant pair (docs/operations.md, "Warm standby"): what
  // it serves of the sensor was heard on the line, the active gateway's polls and the sensor's
  // replies; nothing is sent to the sensor from here (status bit 7). Set as it is published.
  bool standby = false;
  std::string firmware;
  // The model as the device itself reports it, where its driver reads one (a device
  // profile's [identity] model); empty: the driver's model() is all there is.
  std::string model;
  // How far the sensor's settings are protected right now, on sensors whose protocol has such
  // a level (0 = locked); none where it has none or it is not known yet.
  std::optional<std::uint16_t> protection_level;
  std::uint32_t bus_address = 0;    // the sensor's address on its bus (follows Set Address)
  // Settings as the sensor holds them (read back or acknowledged): what holding registers show.
  KnownSettings settings;
  SensorCounters counters;
};

// The sensor itself did not answer its last exchange: offline, not merely not heard from yet
// (online is false until the first exchange ends), nor cut off by a tty that is gone.
inline bool known_offline(const SensorState& state) { return !state.online && state.unanswered; }

// Whether the sensor counts as online at `now`: its last exchange got a valid reply, and it has
// been heard from within `silence_limit` (its stale_after). The second half matters while a
// poll of a sensor that fell silent is still running its retries, each with its late-reply
// window and each a turn of its own between the other sensors' polls (with the defaults well
// over a second): it clears the online bit no later than the measurements turn stale. Heard from: its last answer, or its
// last reading, which is taken when the measurement's answer arrived.
inline bool online_at(const SensorState& state, SteadyClock::time_point now,
                      std::chrono::milliseconds silence_limit) {
  if (!state.online) return false;
  std::optional<SteadyClock::time_point> heard = state.last_answer;
  if (state.reading && (!heard || state.reading->taken > *heard)) heard = state.reading->taken;
  return !heard || now - *heard <= silence_limit;
}

}  // namespace tiltgate
