#include "sparkplug/device_sampler.h"

#include <cstdlib>

#include "gateway/status_copy.h"
#include "mapping/model_capabilities.h"
#include "settings/sensor_settings.h"

namespace tiltgate::sparkplug {

namespace {

std::int64_t steady_ms(SteadyClock::time_point at) {
  return std::chrono::duration_cast<std::chrono::milliseconds>(at.time_since_epoch()).count();
}

// A clock step (NTP, an operator) larger than this moves the readings' times with it.
constexpr std::int64_t kClockStepMs = 1000;

}  // namespace

DeviceSampler::DeviceSampler(const Gateway& gateway, FamilyList families)
    : gateway_(gateway), families_(families) {}

void DeviceSampler::follow_clock(SteadyClock::time_point now, std::int64_t now_unix_ms) {
  const std::int64_t offset = now_unix_ms - steady_ms(now);
  if (!offset_ms_ || std::llabs(offset - *offset_ms_) > kClockStepMs) offset_ms_ = offset;
}

std::int64_t DeviceSampler::unix_ms_of(SteadyClock::time_point taken) const {
  return steady_ms(taken) + offset_ms_.value_or(0);
}

std::vector<DeviceSample> DeviceSampler::sample(SteadyClock::time_point now,
                                                std::int64_t now_unix_ms) {
  follow_clock(now, now_unix_ms);
  const WordOrder order = gateway_.config().server.word_order;
  std::vector<DeviceSample> samples;
  for (const std::shared_ptr<GatewaySensor>& sensor : gateway_.sensors()) {
    const SensorStatus status = sensor_status(*sensor, now);
    const std::shared_ptr<const SensorSnapshot> snapshot = sensor->snapshot();
    const SensorView view = sensor->view(*snapshot, now, order);
    DeviceSample s;
    s.name = status.name;
    s.model = status.model;
    s.serial = status.serial;
    s.firmware = status.firmware;
    s.single_axis = sensor->model != nullptr && sensor->model->axes == 1;
    s.online = status.online;
    s.stale = status.stale;
    s.wrong_device = status.wrong_device;
    s.angle_x = status.x;
    s.angle_y = s.single_axis ? std::nullopt : status.y;
    s.tilt = status.tilt;
    s.relative_x = status.relative_x;
    s.relative_y = s.single_axis ? std::nullopt : status.relative_y;
    s.has_lever = sensor->config.lever_m.has_value();
    s.displacement_mm = status.displacement_mm;
    s.reports_temperature =
        reports_temperature(sensor->model, sensor->config.family_options.device_values());
    s.temperature = status.temperature;
    s.status = view.status();
    s.alarms = status.alarms;
    s.alarms_danger = status.alarms_danger;
    s.alarms_latched = status.alarms_latched;
    s.age_ms = status.age_ms;
    if (snapshot->state.reading) s.reading_unix_ms = unix_ms_of(snapshot->state.reading->taken);
    for (const SensorSetting& setting : sensor_settings(sensor->map, families_))
      s.settings.push_back({setting.name, setting_value(setting, snapshot->state)});
    samples.push_back(std::move(s));
  }
  return samples;
}

}  // namespace tiltgate::sparkplug
