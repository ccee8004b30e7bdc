#include "settings/setting_writer.h"

#include <fmt/format.h>

#include <algorithm>

#include "line_scheduling/bus_scheduler.h"
#include "line_scheduling/sensor_write.h"
#include "mapping/map_access.h"
#include "settings/sensor_settings.h"

namespace tiltgate {

namespace {

std::string fault_text(MapFault fault) {
  switch (fault) {
    case MapFault::illegal_value: return "the value is out of the setting's range";
    case MapFault::illegal_address: return "the setting is not writable";
    case MapFault::no_such_table: return "the map has no holding registers";
    case MapFault::unavailable: return "the sensor is unavailable";
  }
  return "refused";
}

SettingOutcome refused(std::string why, std::optional<double> old_value = std::nullopt) {
  return SettingOutcome{SettingOutcome::Result::refused, std::move(why), old_value, {}};
}

}  // namespace

SettingWriter::SettingWriter(const Gateway& gateway, FamilyList families)
    : gateway_(gateway), families_(families) {}

boost::asio::awaitable<SettingOutcome> SettingWriter::write(std::string sensor_name,
                                                            std::string setting_name, double value,
                                                            WriteOrigin origin) const {
  const auto& sensors = gateway_.sensors();
  const auto found = std::find_if(sensors.begin(), sensors.end(), [&](const auto& sensor) {
    return sensor->config.name == sensor_name;
  });
  if (found == sensors.end()) co_return refused("no such sensor");
  // Held to the end: a reload may drop the sensor while the write waits for its bus.
  std::shared_ptr<GatewaySensor> sensor = *found;
  const std::vector<SensorSetting> settings =
      sensor_settings(sensor->map, families_, &sensor->driver->state());
  const auto setting =
      std::find_if(settings.begin(), settings.end(),
                   [&](const SensorSetting& s) { return s.name == setting_name; });
  if (setting == settings.end())
    co_return refused(fmt::format("{} is not a setting of its map", setting_name));
  const std::optional<double> old_value = setting->value;
  const ServerConfig& server = gateway_.config().server;
  auto plan = plan_point_write(sensor->map, server.word_order, *setting->point, value);
  if (!plan) co_return refused(fault_text(plan.error()), old_value);
  const std::shared_ptr<BusScheduler> bus = sensor->bus;
  if (bus == nullptr) co_return refused("no bus polls the sensor", old_value);
  const auto deadline = SteadyClock::now() + server.write_timeout;
  SensorWrite job(std::move(sensor), std::move(*plan), std::move(origin));  // named: see BusScheduler::write()
  // What the bus refuses before queueing (another device at the address, an address another
  // sensor has, a value the driver does not take) is never sent: refused, not a NAK. (The
  // bus's write admits it again: the second look finds the same, and logs nothing new.)
  if (WriteResult admissible = job.admit(*bus); !admissible)
    co_return refused(admissible.error().detail, old_value);
  WriteResult done = co_await bus->write(std::move(job), deadline);
  SettingOutcome outcome =
      done ? SettingOutcome{SettingOutcome::Result::ack, {}, {}, {}} : outcome_of(done.error());
  outcome.old_value = old_value;
  co_return outcome;
}

}  // namespace tiltgate
