#include "line_scheduling/sensor_write.h"

#include <algorithm>
#include <fmt/format.h>
#include <span>
#include <spdlog/spdlog.h>

#include "audit/audit_trail.h"
#include "driver/visible_text.h"
#include "line_scheduling/bus_scheduler.h"

namespace tiltgate {

namespace asio = boost::asio;

namespace {

// The audit trail's result (audit/audit_record.h) of a setting the driver was handed and did
// not carry out: the sensor's refusal with its code, its silence, or why the driver refused.
std::string audit_result(const WriteError& error, std::optional<std::uint8_t> refusal_code) {
  switch (error.kind) {
    case WriteErrorKind::rejected:
    case WriteErrorKind::refused:
      return refusal_code ? fmt::format("nak 0x{:02X}", *refusal_code) : "nak";
    case WriteErrorKind::device_exception:
      return fmt::format("nak 0x{:02X}", error.device_exception);
    case WriteErrorKind::no_response: return "timeout";
    case WriteErrorKind::busy: return "error: " + error.detail;
    case WriteErrorKind::not_supported:
    case WriteErrorKind::bad_value: return "refused: " + error.detail;
  }
  return "error: " + error.detail;
}

std::string value_text(double value) { return fmt::format("{}", value); }

}  // namespace

SensorWrite::SensorWrite(std::shared_ptr<GatewaySensor> sensor, std::vector<PlannedWrite> plan,
                         WriteOrigin origin)
    : sensor_(std::move(sensor)), plan_(std::move(plan)), origin_(std::move(origin)) {
  for (const PlannedWrite& step : plan_) settings_.push_back({*step.point->write, step.value});
}

WriteResult SensorWrite::check(const BusScheduler& bus, std::size_t first) const {
  // A zero meant for the configured sensor is not applied to the device answering in its place.
  const SensorState& state = sensor_->driver->state();
  // [audit] when_full = "refuse": no change the trail cannot keep on disk.
  if (bus.audit() != nullptr && !bus.audit()->accepts_changes())
    return Unexpected(WriteError{WriteErrorKind::refused, std::string(kAuditRefusesChanges)});
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
  if (!checked) {
    spdlog::warn("{}: write refused: {}", sensor_->config.name,
                 visible_text(checked.error().detail));
    audit_rest(bus, 0, "refused: " + checked.error().detail);
  }
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
  const std::optional<double> old_value =
      sensor_->driver->state().settings.get(settings_[index].target);
  WriteResult done = check(bus, index);
  if (!done) {
    audit(bus, index, old_value, "refused: " + done.error().detail);
  } else {
    done = co_await sensor_->driver->write(line, settings_[index].target, step.value);
    ++sent;
    audit(bus, index, old_value,
          done ? std::string("ack")
               : audit_result(done.error(), sensor_->driver->state().counters.last_refusal));
  }
  if (!done) {
    log_failure(index, done.error());
    sensor_->driver->abandon(std::span(settings_).first(index));
    co_return done;
  }
  spdlog::info("{}: wrote {} = {}", sensor_->config.name, visible_text(step.point->name),
               step.value);
  std::copy(step.words.begin(), step.words.end(),
            sensor_->written.begin() + step.point->address);
  co_return done;
}

WriteResult SensorWrite::fail(const BusScheduler& bus, WriteError why) const {
  if (!plan_.empty()) log_failure(0, why);
  // Never handed to the driver: the sensor offline, the bus too busy or stopping.
  audit_rest(bus, 0, "error: " + why.detail);
  return Unexpected{std::move(why)};
}

void SensorWrite::log_failure(std::size_t index, const WriteError& error) const {
  const PlannedWrite& step = plan_[index];
  spdlog::warn("{}: write {} = {} failed: {}", sensor_->config.name,
               visible_text(step.point->name), step.value, visible_text(error.detail));
}

void SensorWrite::audit(const BusScheduler& bus, std::size_t index,
                        std::optional<double> old_value, std::string result) const {
  AuditTrail* trail = bus.audit();
  if (trail == nullptr) return;
  AuditRecord record;
  record.origin = origin_;
  record.sensor = sensor_->config.bus + "/" + sensor_->config.name;
  record.setting = plan_[index].point->name;
  if (old_value) record.old_value = value_text(*old_value);
  record.new_value = value_text(plan_[index].value);
  record.result = std::move(result);
  trail->record(std::move(record));
}

void SensorWrite::audit_rest(const BusScheduler& bus, std::size_t first,
                             const std::string& result) const {
  for (std::size_t i = first; i < plan_.size(); ++i)
    audit(bus, i, sensor_->driver->state().settings.get(settings_[i].target), result);
}

}  // namespace tiltgate
