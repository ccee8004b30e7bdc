#include "config/redundancy_checks.h"

#include <fmt/format.h>

#include "device_server/port_url.h"

namespace tiltgate::config {

namespace {

// Behind a device server (one client per port) or on a bus whose devices speak TCP there is
// no line for the standby to listen to: their quiet says nothing of the primary.
bool standby_listens_to(const ParsedBus& bus) {
  if (!bus.where.valid("port")) return false;
  const auto port = parse_port(bus.config.port);
  return port && !port->over_network();
}

// The sensor of `bus` polled most often; none when the bus has no sensors (pass-through only).
const ParsedSensor* most_polled_on(const ParsedBus& bus, const std::vector<ParsedSensor>& sensors) {
  const ParsedSensor* fastest = nullptr;
  for (const ParsedSensor& sensor : sensors) {
    if (!sensor.where.valid("bus") || sensor.config.bus != bus.config.name ||
        !sensor.where.usable("poll_ms"))
      continue;
    if (fastest == nullptr || sensor.config.poll < fastest->config.poll) fastest = &sensor;
  }
  return fastest;
}

}  // namespace

void check_takeover(const ParsedRedundancy& redundancy, const std::vector<ParsedBus>& buses,
                    const std::vector<ParsedSensor>& sensors, ErrorList& errors) {
  if (!redundancy.where.usable("takeover_ms")) return;
  const std::chrono::milliseconds takeover = redundancy.config.takeover;
  for (const ParsedBus& bus : buses) {
    if (!bus.where.valid("name") || !standby_listens_to(bus)) continue;
    const ParsedSensor* fastest = most_polled_on(bus, sensors);
    if (fastest == nullptr) continue;
    // A live primary sends a request on this line at least every shortest poll; twice that
    // leaves room for one poll that comes late (a slow reply, retries, another sensor's turn).
    const std::chrono::milliseconds needed = 2 * fastest->config.poll;
    if (takeover >= needed) continue;
    redundancy.where.report(
        errors, "takeover_ms",
        fmt::format("{} ms{} is less than twice the shortest poll_ms on bus \"{}\" ({} ms, "
                    "sensor \"{}\"): a live primary leaves that line quiet for up to a poll "
                    "period between requests, and the standby would take the lines over from "
                    "it. Raise takeover_ms to at least {}, or poll a sensor of bus \"{}\" every "
                    "{} ms or less",
                    takeover.count(),
                    redundancy.where.valid("takeover_ms") ? "" : " (the default)",
                    bus.config.name, fastest->config.poll.count(), fastest->config.name,
                    needed.count(), bus.config.name, takeover.count() / 2));
  }
}

}  // namespace tiltgate::config
