// How old a healthy sensor's reading can get while other sensors on its line fail: the worst
// case of the line's turns (line_scheduling/line_turns.h) as a formula of the line's settings and
// sensors, docs/operations.md "One failing sensor never takes its line". Pure: `tiltgate check`
// prints its warnings, and the gateway logs them at start and at each reload.
//
// For a healthy sensor S on a line where k other sensors fail at once (k = 2, or fewer when
// the line has fewer others):
//
//   worst age of S = Q + L + p,  Q = poll_ms of S + R where R < poll_ms (the line keeps up),
//                                    R otherwise
//
//   p  one healthy poll: the wire time of its characters (ProtocolDescriptor::poll_size), and
//      per exchange the bus's gap and 1 ms for the sensor to turn round; on a bus without a
//      serial line (baud 0, devices that speak TCP) the reply wait per exchange;
//   R  one poll of each of the line's other healthy sensors;
//   W  the longest turn of a failing sensor: its request's wire time, its reply wait and the
//      late-reply window (serial/late_window.h), with a reply wait adapted up to max_timeout_ms;
//   s  a short look: the request's wire time, timeout_ms and 20 ms;
//   L  W + k x s where replies name their sender (each may fall silent in a round that
//      follows another kind of turn, and one takes a whole turn between two rounds); k x W
//      where they do not (every time-out there keeps the whole window).
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "config/config.h"
#include "driver/family.h"

namespace tiltgate {

// One sensor's bound.
struct SensorAgeBound {
  std::string sensor;
  std::chrono::milliseconds worst_age{0};
  std::chrono::milliseconds stale_after{0};
};

struct LineBudget {
  std::string bus;
  int failing = 0;                           // k
  std::chrono::milliseconds poll{0};         // p
  std::chrono::milliseconds others{0};       // R for the sensor below
  std::chrono::milliseconds failing_turn{0}; // W
  std::chrono::milliseconds short_look{0};   // s
  std::chrono::milliseconds failures{0};     // L
  std::vector<SensorAgeBound> sensors;       // in the configuration's order
};

// The budget of `bus`, whose sensors are `sensors` (the configuration's, those on other buses
// skipped), its protocol `protocol`, with `failing` sensors failing at once.
LineBudget line_budget(const BusConfig& bus, const std::vector<SensorConfig>& sensors,
                       const ProtocolDescriptor& protocol, int failing = 2);

// One warning for each bus where a sensor's bound is past its stale_ms, naming the sensor with
// the least room, the terms and what to change.
std::vector<std::string> line_budget_warnings(const Config& config, FamilyList families);

}  // namespace tiltgate
