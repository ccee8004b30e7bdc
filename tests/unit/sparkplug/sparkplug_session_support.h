// What the edge node session's tests share: a node "gw1" in group "plant" with the sensors
// "boom" (dual-axis, settings filter and zero_x) and "mast" (single-axis), their samples, the
// time, and the actions a call returned picked apart.
#pragma once

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sparkplug/edge_node_session.h"
#include "sparkplug/topic.h"

namespace tiltgate::sparkplug::test {

using namespace std::chrono_literals;

inline constexpr std::int64_t kUnixStart = 1796176370000;

// `ms` after the tests' start, on both clocks.
inline Instant at(std::int64_t ms) {
  return Instant{std::chrono::steady_clock::time_point{} + std::chrono::hours(1) +
                     std::chrono::milliseconds(ms),
                 kUnixStart + ms};
}

inline EdgeNodeOptions options() {
  EdgeNodeOptions o;
  o.group_id = "plant";
  o.edge_node_id = "gw1";
  o.node = NodeInfo{"0.1.0", 2};
  o.on_change_deg = 0.5;
  o.min_interval = 100ms;
  o.max_interval = 10000ms;
  return o;
}

// A sensor online with a fresh reading taken `read_ms` after the start.
inline DeviceSample reading(std::string name, std::string model, double x, std::optional<double> y,
                            std::int64_t age_ms, std::int64_t read_ms) {
  DeviceSample s;
  s.name = std::move(name);
  s.model = std::move(model);
  s.single_axis = !y.has_value();
  s.online = true;
  s.stale = false;
  s.angle_x = x;
  s.angle_y = y;
  s.tilt = std::max(std::abs(x), std::abs(y.value_or(0.0)));
  s.age_ms = age_ms;
  s.reading_unix_ms = kUnixStart + read_ms;
  return s;
}

inline DeviceSample boom(double x, double y = 0.0, std::int64_t read_ms = 0) {
  DeviceSample s = reading("boom", "h6", x, y, 3, read_ms);
  s.serial = "9600223";
  s.firmware = "Rev A.8";
  s.settings = {{"filter", 4.0}, {"zero_x", std::nullopt}};
  return s;
}

// Single-axis, its serial and firmware not read yet.
inline DeviceSample mast(double x, std::int64_t read_ms = 0) {
  return reading("mast", "h4360", x, std::nullopt, 70, read_ms);
}

inline DeviceSample offline(DeviceSample s) {
  s.online = false;
  s.stale = true;
  return s;
}

inline EdgeNodeSession make_session(EdgeNodeOptions o = options(),
                                    std::optional<std::uint8_t> last_bd_seq = std::nullopt) {
  auto session = EdgeNodeSession::create(std::move(o), {"boom", "mast"}, last_bd_seq);
  REQUIRE(session.has_value());
  return std::move(*session);
}

template <class T>
std::vector<T> all_of(const std::vector<Action>& actions) {
  std::vector<T> out;
  for (const Action& a : actions) {
    if (const auto* x = std::get_if<T>(&a)) out.push_back(*x);
  }
  return out;
}

inline std::vector<Publish> publishes(const std::vector<Action>& actions) {
  return all_of<Publish>(actions);
}

inline std::vector<std::string> topics(const std::vector<Action>& actions) {
  std::vector<std::string> out;
  for (const Action& a : actions) {
    if (const auto* p = std::get_if<Publish>(&a)) out.push_back(p->topic);
    if (const auto* s = std::get_if<Subscribe>(&a)) out.push_back("subscribe " + s->topic);
    if (const auto* k = std::get_if<Keep>(&a)) out.push_back("keep " + k->topic);
    if (std::holds_alternative<Disconnect>(a)) out.push_back("disconnect");
  }
  return out;
}

inline const Metric* find_metric(const Payload& payload, std::string_view name) {
  for (const Metric& m : payload.metrics) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

inline const Metric* find_alias(const Payload& payload, std::uint64_t alias) {
  for (const Metric& m : payload.metrics) {
    if (m.alias == alias) return &m;
  }
  return nullptr;
}

// A session connected (no primary host) with both sensors sampled before the CONNACK: the
// births are out, and these are the actions on_connected() returned.
struct LiveSession {
  EdgeNodeSession session = make_session();
  std::vector<Action> connected;

  explicit LiveSession(EdgeNodeOptions o = options()) : session(make_session(std::move(o))) {
    const DeviceSample samples[] = {boom(1.0), mast(3.0)};
    (void)session.update(samples, at(0));
    (void)session.begin_connect(at(0));
    connected = session.on_connected(at(0));
  }
};

inline std::vector<std::uint8_t> command(const std::vector<Metric>& metrics) {
  return encode(Payload{static_cast<std::uint64_t>(kUnixStart), std::nullopt, metrics});
}

}  // namespace tiltgate::sparkplug::test
