#include "gateway/sensor_write.h"

#include <algorithm>
#include <fmt/format.h>
#include <span>
#include <spdlog/spdlog.h>

#include "gateway/bus_scheduler.h"

namespace tiltgate {

namespace asio = boost::asio;

SensorWrite::SensorWrite(std::shared_ptr<GatewaySensor> sensor, std::vector<PlannedWrite> plan)
    : sensor_(std::move(sensor)), plan_(std::move(plan)) {
  for (const PlannedWrite& step : plan_) settings_.push_back({*step.point->write, step.value});
}

WriteResult SensorWrite::check(const BusScheduler& bus, std::size_t first) const {
  // A zero meant for the configured sensor is not applied to the device answering in its place.
  const SensorState& state = sensor_->driver->state();
  if (state.wrong_device) {
    return Unexpected(WriteError{
        WriteErrorKind::refused,
        fmt::format("wrong device: serial '{}' answers at address {}, not the configured '{}'",
                    state.serial, state.bus_address, sensor_->config.serial)});
  }
  const auto settings = std::span(settings_).subspan(first);
  WriteResult checked = sensor_->driver->check_writes(settings);
  for (const SettingWrite& setting : settings) {
    if (!checked) break;
    checked = bus.check_address_free(*sensor_, setting.target, setting.value);
  }
  return checked;
}

WriteResult SensorWrite::admit(const BusScheduler& bus) const {
  WriteResult checked = check(bus);
  if (!checked) spdlog::warn("{}: write refused: {}", sensor_->config.name, checked.error().detail);
  return checked;
}

asio::awaitable<WriteResult> SensorWrite::run(Line& line, const BusScheduler& bus,
                                              std::uint64_t& sent) {
  WriteResult result = Done{};
  for (std::size_t i = 0; i < plan_.size() && result; ++i)
    result = co_await write_setting(line, bus, i, sent);
  sensor_->publish();
  co_return result;
}

asio::awaitable<WriteResult> SensorWrite::write_setting(Line& line, const BusScheduler& bus,
                                                        std::size_t index, std::uint64_t& sent) {
  const PlannedWrite& step = plan_[index];
  WriteResult done = check(bus, index);
  if (done) {
    done = co_await sensor_->driver->write(line, settings_[index].target, step.value);
    ++sent;
  }
  if (!done) {
    log_failure(index, done.error());
    sensor_->driver->abandon(std::span(settings_).first(index));
    co_return done;
  }
  spdlog::info("{}: wrote {} = {}", sensor_->config.name, step.point->name, step.value);
  std::copy(step.words.begin(), step.words.end(),
            sensor_->written.begin() + step.point->address);
  co_return done;
}

WriteResult SensorWrite::fail(WriteError why) const {
  if (!plan_.empty()) log_failure(0, why);
  return Unexpected{std::move(why)};
}

void SensorWrite::log_failure(std::size_t index, const WriteError& error) const {
  const PlannedWrite& step = plan_[index];
  spdlog::warn("{}: write {} = {} failed: {}", sensor_->config.name, step.point->name,
               step.value, error.detail);
}

}  // namespace tiltgate
