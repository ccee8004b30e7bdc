#include "sparkplug/setting_writer.h"

#include <fmt/format.h>

#include <algorithm>

#include "gateway/bus_scheduler.h"
#include "gateway/sensor_write.h"
#include "mapping/map_access.h"
#include "sparkplug/sensor_settings.h"

namespace tiltgate::sparkplug {

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

}  // namespace

SettingWriter::SettingWriter(const Gateway& gateway, FamilyList families)
    : gateway_(gateway), families_(families) {}

boost::asio::awaitable<std::optional<std::string>> SettingWriter::write(Write write) const {
  using Result = std::optional<std::string>;
  const auto& sensors = gateway_.sensors();
  const auto found = std::find_if(sensors.begin(), sensors.end(), [&](const auto& sensor) {
    return sensor->config.name == write.device;
  });
  if (found == sensors.end()) co_return Result("no such sensor");
  // Held to the end: a reload may drop the sensor while the write waits for its bus.
  std::shared_ptr<GatewaySensor> sensor = *found;
  const std::vector<SensorSetting> settings = sensor_settings(sensor->map, families_);
  const auto setting =
      std::find_if(settings.begin(), settings.end(),
                   [&](const SensorSetting& s) { return s.name == write.setting; });
  if (setting == settings.end())
    co_return Result(fmt::format("{} is not a setting of its map", write.setting));
  const ServerConfig& server = gateway_.config().server;
  auto plan = plan_point_write(sensor->map, server.word_order, *setting->point, write.value);
  if (!plan) co_return Result(fault_text(plan.error()));
  const std::shared_ptr<BusScheduler> bus = sensor->bus;
  if (bus == nullptr) co_return Result("no bus polls the sensor");
  const auto deadline = SteadyClock::now() + server.write_timeout;
  const std::optional<std::string>& host = gateway_.config().sparkplug.primary_host_id;
  const WriteOrigin origin{"sparkplug", host ? "host " + *host : "a DCMD"};
  SensorWrite job(std::move(sensor), std::move(*plan), origin);  // named: see BusScheduler::write()
  WriteResult done = co_await bus->write(std::move(job), deadline);
  if (!done)
    co_return Result(done.error().detail.empty() ? std::string("refused") : done.error().detail);
  co_return Result{};
}

}  // namespace tiltgate::sparkplug
