#include "line_scheduling/line_budget.h"

#include <algorithm>
#include <fmt/format.h>

#include "driver/scan.h"
#include "line_scheduling/gateway_sensor.h"
#include "serial/late_window.h"

namespace tiltgate {

namespace {

using std::chrono::milliseconds;

// A sensor's turnaround allowance per exchange: "as fast as possible" by the documents, plus a
// USB adapter's latency with its low-latency flag set (serial/low_latency.h).
constexpr std::chrono::microseconds kTurnaround{1000};

// Bits a character takes on the wire: a start bit, 8 data bits, a parity bit or a second stop
// bit where the framing has one, and a stop bit.
unsigned bits_per_character(Framing framing) {
  return framing == Framing::eight_none_one ? 10 : 11;
}

milliseconds whole_ms(std::chrono::microseconds us) {
  return std::chrono::ceil<milliseconds>(us);
}

}  // namespace

LineBudget line_budget(const BusConfig& bus, const std::vector<SensorConfig>& sensors,
                       const ProtocolDescriptor& protocol, int failing) {
  std::vector<const SensorConfig*> on_bus;
  for (const SensorConfig& sensor : sensors)
    if (sensor.bus == bus.name) on_bus.push_back(&sensor);
  LineBudget budget;
  budget.bus = bus.name;
  const int count = int(on_bus.size());
  budget.failing = std::clamp(failing, 0, std::max(count - 1, 0));
  const Framing framing = bus.framing.value_or(protocol.framing);
  const unsigned bits = bits_per_character(framing);
  const PollSize& size = protocol.poll_size;
  const auto per_exchange =
      std::chrono::duration_cast<std::chrono::microseconds>(bus.gap) + kTurnaround;
  budget.poll = whole_ms(
      wire_time(std::size_t(size.request_characters + size.reply_characters), bits, bus.baud) +
      size.exchanges * per_exchange);
  // Baud 0: no serial line under the bus (devices that speak TCP themselves), so no wire time
  // to count; an exchange takes what the device and the network take, at most the reply wait.
  if (bus.baud == 0) budget.poll = size.exchanges * bus.timeout;
  const auto request = wire_time(
      std::size_t(size.request_characters / std::max(size.exchanges, 1)), bits, bus.baud);
  const LateWindow window{bus.timeout, bus.late_guard};
  budget.failing_turn = whole_ms(request) + window.held_after(bus.max_timeout);
  budget.short_look = whole_ms(request) + window.looked_after(bus.timeout);
  if (budget.failing > 0) {
    // Each may fall silent in a round after a turn of another kind (a short look), and one
    // of them takes a whole turn between two rounds.
    budget.failures = protocol.replies_name_sender
                          ? budget.failing_turn + budget.failing * budget.short_look
                          : budget.failing * budget.failing_turn;
  }
  const int healthy_others = std::max(count - 1 - budget.failing, 0);
  budget.others = healthy_others * budget.poll;
  for (const SensorConfig* sensor : on_bus) {
    SensorAgeBound bound;
    bound.sensor = sensor->name;
    bound.stale_after = sensor->stale_after.value_or(default_stale_after(sensor->poll));
    // A line that keeps up polls S at its period, and one other turn may start just before it
    // is due; on a line that does not, S waits for one round of the others.
    const auto rounds = budget.others < sensor->poll ? sensor->poll + budget.others : budget.others;
    bound.worst_age = rounds + budget.failures + budget.poll;
    budget.sensors.push_back(bound);
  }
  return budget;
}

std::vector<std::string> line_budget_warnings(const Config& config, FamilyList families) {
  std::vector<std::string> warnings;
  for (const BusConfig& bus : config.buses) {
    const ProtocolEntry protocol = find_protocol(families, bus.protocol);
    if (protocol.protocol == nullptr) continue;  // the loader refuses it
    const LineBudget budget = line_budget(bus, config.sensors, *protocol.protocol);
    if (budget.failing == 0) continue;
    // The sensor with the least room: its bound furthest past its stale_ms.
    const auto over = [](const SensorAgeBound& b) { return b.worst_age - b.stale_after; };
    const SensorAgeBound* tightest = nullptr;
    for (const SensorAgeBound& bound : budget.sensors)
      if (over(bound) > milliseconds(0) && (!tightest || over(bound) > over(*tightest)))
        tightest = &bound;
    if (tightest == nullptr) continue;
    warnings.push_back(fmt::format(
        "bus \"{}\": while {} of its sensors fail at once, the reading of \"{}\" can get {} ms "
        "old, past its stale_ms ({} ms): {} ms of the other sensors' polls, {} ms of failing "
        "sensors' turns ({} ms each{}), {} ms of its own poll. Lower max_timeout_ms or "
        "late_guard_ms, raise baud or stale_ms, or share the sensors out over more buses "
        "(docs/operations.md, \"One failing sensor never takes its line\")",
        bus.name, budget.failing, tightest->sensor, tightest->worst_age.count(),
        tightest->stale_after.count(), budget.others.count(), budget.failures.count(),
        budget.failing_turn.count(),
        protocol.protocol->replies_name_sender
            ? ""
            : fmt::format("; replies on {} name no sender, so every time-out keeps the line "
                          "for its whole late-reply window",
                          bus.protocol),
        budget.poll.count()));
  }
  return warnings;
}

}  // namespace tiltgate
